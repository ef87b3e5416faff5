// Kautz, Heidrich & Seidel 2001, section 3.1: the normal density function (NDF) p(n_m) of a
// microfacet surface, the one input of fractal bump-map synthesis.
#pragma once

#include "meso/core/math.h"

#include <cstdint>
#include <string>

namespace meso {

// A microfacet normal distribution D(m) in its own tangent frame (x = the NDF's principal axis,
// z = the macro normal). Contract of every implementation:
//  - D(m) is a density per unit solid angle of the unit microfacet normal m, >= 0, 0 for m.z <= 0,
//    never NaN or Inf for any unit m (also at m.z -> 0 and for extreme roughness);
//  - it is normalized by projected area:  integral over the hemisphere of D(m) cos(theta_m) dw = 1.
//    Equivalently, D is the probability density of (m.x, m.y) over the unit disk, because
//    dA(disk) = cos(theta_m) dw: the paper's "2D hemispherical map" of the normal's x and y is D.
//  - immutable after construction: every method is safe to call from many threads at once.
class Ndf {
 public:
  virtual ~Ndf() = default;
  // D(m), m a unit vector in the NDF's frame.
  virtual float D(const Vec3& m) const = 0;
  // Half-widths (sx, sy) of the box |m.x| <= sx, |m.y| <= sy (inside [0, 1]^2) that holds all but a
  // negligible fraction (< 1e-6) of the projected-area mass: the lookup table spends its resolution
  // there, which keeps sharp NDFs (Beckmann alpha 1e-4) resolvable.
  virtual Vec2 support() const { return Vec2(1.0f); }
  // Short human-readable description ("beckmann(0.3, 0.1)").
  virtual std::string name() const = 0;
  // Hash of everything that shapes D: part of a table's cache key.
  virtual uint64_t fingerprint() const = 0;
};

}  // namespace meso
