// Becker & Max 1993, end of section 3: Perlin's volume textures as heights, a relief without a
// parameterization (docs/solid-relief.md). Gradient-noise fBm over 3-D space.
#pragma once

#include "meso/relief/height_source.h"

#include <cstdint>
#include <vector>

namespace meso {

struct SolidNoiseOptions {
  int octaves = 4;
  float lacunarity = 2.0f;  // frequency ratio of successive octaves (rounded per octave)
  float gain = 0.5f;        // amplitude ratio of successive octaves
  uint64_t seed = 0;
  int firstOctave = 0;  // only octaves firstOctave .. octaves - 1 (relief.split_octaves)
  // Wrap every octave's lattice so that the noise repeats every `period` along x, y and z: the
  // form the tables trace (SolidSlice). The renderer's noise does not repeat.
  bool periodic = false;
  // The period in noise units (octave-0 lattice cells), a multiple of 3 (Q's denominator); 0:
  // solidTilePeriod of these options.
  int period = 0;
};

// The most cycles of a level's finest octave that one table tile holds: the tables trace
// render.tables.mesh_resolution (192) quads per tile side, 4 per cycle.
inline constexpr int kSolidTileCycles = 48;

// The period the tables' tile gets: the largest multiple of 3 at which the finest octave has at
// most kSolidTileCycles cycles per tile (at least 3). The more cells of its coarsest octave a tile
// holds, the closer its statistics are to the whole noise's: two octaves on tiles of 6 cells in six
// orientations were 0.9% apart in intensity at theta_V = 80, on tiles of 24 cells 0.2%.
int solidTilePeriod(const SolidNoiseOptions& options);

// Sum over octaves o of gain^o * noise(Q f_o q + c_o): 3-D Perlin gradient noise (a hashed unit
// gradient, one of 4096 spread evenly over the sphere, per lattice point; quintic fade) at integer
// frequencies f_o = round(lacunarity^o) lattice cells per unit of q. The lattice is turned by the
// rational rotation Q = [[1, 2, 2], [2, 1, -2], [2, -2, 1]] / 3 and shifted by a per-octave offset
// c_o, so that no plane along the axes of q (a ground at y = 0, a cube's faces) is a lattice
// plane: gradient noise is not homogeneous (its rms slope on a lattice plane is 12% above that on
// the plane halfway between), and surfaces along the axes would otherwise see the lattice planes'
// statistics instead of those of the tables (docs/solid-relief.md). Q's entries are thirds, so
// periodic lattices exist that repeat every multiple of 3 along the axes of q. Deterministic per
// seed; gradients are exact.
class SolidNoise {
 public:
  explicit SolidNoise(const SolidNoiseOptions& options);

  float height(Vec3 q) const;
  Vec3 gradient(Vec3 q) const;
  // height(q) and gradient(q) bit for bit, in one pass.
  float heightAndGradient(Vec3 q, Vec3& gradient) const;
  // The last octave's frequency, lattice cells per unit of q.
  float highestFrequency() const;
  // The lowest octave's frequency (of octaves firstOctave ..), lattice cells per unit of q.
  float lowestFrequency() const;
  // sum over octaves of |gain^o| times sqrt(3)/2, the bound of 3-D gradient noise with unit
  // gradients.
  float maxAbsHeight() const;
  uint64_t fingerprint() const;
  const SolidNoiseOptions& options() const { return options_; }
  // The period along each axis when periodic (options.period, or solidTilePeriod).
  int period() const { return period_; }

 private:
  struct Octave {
    int frequency;
    float weight;
    uint64_t salt;
    Vec3 offset;
  };
  float octave(const Octave& o, Vec3 q, Vec3* grad) const;
  SolidNoiseOptions options_;
  int period_ = 3;
  std::vector<Octave> octaves_;
};

// A planar slice of a periodic SolidNoise as a 2-D height source over one tile: h(x, y) =
// noise(L (x a + y b)) for (x, y) in [0, 1)^2, where a and b are orthonormal and L a and L b are
// periods of the noise (integer multiples of its period along each axis), so the slice tiles.
// The default is the plane z = 0 with L the period: the tile the tables of a solid level trace.
class SolidSlice : public HeightSource {
 public:
  // Throws meso::Error unless noise is periodic, a and b are orthonormal and L a, L b are periods.
  // side <= 0: the noise's period.
  SolidSlice(SolidNoiseOptions noise, Vec3 a = {1, 0, 0}, Vec3 b = {0, 1, 0}, float side = 0.0f);
  float height(Vec2 p) const override;
  Vec2 gradient(Vec2 p) const override;
  float heightAndGradient(Vec2 p, Vec2& g) const override;
  // side * the noise's highest frequency: lattice cells per tile along any line.
  float highestFrequency() const override;
  float lowestFrequency() const override { return side_ * noise_.lowestFrequency(); }
  uint64_t fingerprint() const override;
  float maxAbsHeight() const override { return noise_.maxAbsHeight(); }
  float side() const { return side_; }

 private:
  SolidNoise noise_;
  Vec3 a_, b_;
  float side_;
};

}  // namespace meso
