// Kautz et al. 2001, section 5.1: shade a synthesized microfacet with the NDF itself (the fractal
// assumption): the half vector, expressed in the microfacet's own frame, indexes D.
#pragma once

#include "meso/core/math.h"
#include "meso/synthesis/ndf.h"

namespace meso {

// The microfacet frame {R x, R y, m} of a microfacet normal m (z >= 0) in the NDF's frame, R the
// smallest rotation that takes z to m. The paper stores a deterministic tangent frame per entry
// of L; this one is computed on the fly, is smooth in m, and is the identity for m = z.
// Returns h expressed in that frame: (h . Rx, h . Ry, h . m).
Vec3 toMicrofacetFrame(const Vec3& m, const Vec3& h);

// The world direction of m, a vector in the NDF's frame, on a surface with unit normal N and
// tangent T (the direction of the NDF's principal x axis; it is made orthogonal to N here, and
// any perpendicular is used when T is zero or parallel to N).
Vec3 ndfFrameToWorld(const Vec3& N, const Vec3& T, const Vec3& m);
// The inverse: a world vector in the NDF's frame.
Vec3 worldToNdfFrame(const Vec3& N, const Vec3& T, const Vec3& w);

struct SynthesizedShading {
  // D(h_m): the NDF at the half vector in the microfacet's frame, per steradian (not clamped;
  // multiply by ks and the light's irradiance for the paper's model).
  float specular = 0.0f;
  // max(0, L . m_world): the Lambert cosine on the synthesized normal (multiply by kd / pi or kd).
  float diffuse = 0.0f;
};

// Inputs are world vectors: N the unit macro normal, T the surface tangent (see ndfFrameToWorld),
// V and L unit directions from the point towards the eye and the light; m the synthesized unit
// normal in the NDF's frame (SynthesisSampler::normal). Both factors are 0 when V or L is below
// the macro surface (N . V <= 0 or N . L <= 0); specular is 0 when V = -L (no half vector).
// Never NaN or Inf for finite inputs (grazing angles, degenerate tangents included).
SynthesizedShading shadeSynthesized(const Ndf& ndf, const Vec3& N, const Vec3& T, const Vec3& V,
                                    const Vec3& L, const Vec3& m);

}  // namespace meso
