// Becker & Max 1993, sections 1 and 4.3: relief levels (amplitude, tiling scale S, freq).
// freq and S are the two factors of the D = c * freq * S of eq. 10.
#pragma once

#include "meso/core/math.h"

#include <cstdint>
#include <limits>
#include <optional>

namespace meso {

// A height function h(x, y) over tile coordinates (x, y) = (S u, S v); one tile is [0, 1)^2.
// Values are in the source's own units ("table units"); a level's amplitude turns them into world
// units. Sources that tile have period 1 in x and y. Implementations are immutable after
// construction, so every method is safe to call from many threads at once, and allocation-free.
class HeightSource {
 public:
  virtual ~HeightSource() = default;
  // h(x, y) in table units.
  virtual float height(Vec2 p) const = 0;
  // (dh/dx, dh/dy): table units per unit of tile coordinate (not per texel).
  virtual Vec2 gradient(Vec2 p) const = 0;
  // h(p) and its gradient at once, equal to height(p) and gradient(p) bit for bit; sources that
  // share the work between them (fBm) override it.
  virtual float heightAndGradient(Vec2 p, Vec2& g) const {
    g = gradient(p);
    return height(p);
  }
  // d^2/dt^2 h(p + t dir) at t = 0, where the source has it in closed form (fBm); nullopt where
  // the caller must difference gradient() itself.
  virtual std::optional<float> secondDerivative(Vec2 /*p*/, Vec2 /*dir*/) const {
    return std::nullopt;
  }
  // Highest frequency with significant energy, in cycles per tile (per unit of x), freq / S.
  virtual float highestFrequency() const = 0;
  // Lowest frequency whose octave carries the source's slopes, cycles per tile: a sum of octaves
  // (fBm) gives its first; a source of one band, or whose spectrum runs down to its period (an
  // image), gives highestFrequency() (its band's width is left to the level's D: levelD).
  virtual float lowestFrequency() const { return highestFrequency(); }
  // Hash of everything that shapes height() and gradient(): part of the table cache key.
  virtual uint64_t fingerprint() const = 0;
  // An upper bound of |h| over the whole plane (table units): the displacement bound of a level is
  // amplitude times this. Sources that cannot bound themselves return infinity (no culling).
  virtual float maxAbsHeight() const { return std::numeric_limits<float>::infinity(); }
  // The mean of h over one tile (table units): the default midlevel, the height that stays on the
  // surface when the relief is displaced. The default samples a 128 x 128 grid of the tile.
  virtual float meanHeight() const;
  // Samples per tile side of a sampled source (texels of an image along its longer side), where
  // its surface is interpolated between samples; 0 for a source defined everywhere (noise).
  virtual int texelsPerSide() const { return 0; }
};

// The parameters of relief level i (DESIGN.md section 1): world height amplitude * h(S u, S v).
// Does not own its source. Plain value type: cheap to copy into per-sample code.
struct HeightLevel {
  const HeightSource* source = nullptr;
  float amplitude = 0.0f;  // world units per table unit
  float scale = 1.0f;      // S: the table repeats every 1/S in u and in v
  float freq = 1.0f;       // highest frequency in cycles per unit of u: source freq * S

  // freq from the source (highestFrequency() * scale).
  static HeightLevel make(const HeightSource& source, float amplitude, float scale) {
    return {&source, amplitude, scale, source.highestFrequency() * scale};
  }

  // World height amplitude * h(S u, S v).
  float height(Vec2 uv) const { return amplitude * source->height(scale * uv); }
  // (B_u, B_v) = amplitude * S * grad h(S u, S v): world units per unit of u and of v (chain rule).
  Vec2 derivatives(Vec2 uv) const { return (amplitude * scale) * source->gradient(scale * uv); }
  // Shortest wavelength lambda = 1 / freq, in units of u (DESIGN.md section 3).
  float wavelength() const { return 1.0f / freq; }
};

}  // namespace meso

// Transitional: code written against the first relief commit includes only this header for the
// concrete sources and the Blinn normal. New code includes what it uses.
#include "meso/relief/blinn_normal.h"
#include "meso/relief/fractal_noise.h"
#include "meso/relief/height_table.h"
