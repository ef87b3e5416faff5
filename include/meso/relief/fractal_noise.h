// Becker & Max 1993, section 2.2 (Perlin's noise as heights): gradient-noise fBm.
// Its gradients are analytic.
#pragma once

#include "meso/relief/height_source.h"

#include <cstdint>
#include <vector>

namespace meso {

struct FractalNoiseOptions {
  int octaves = 4;
  float lacunarity = 2.0f;  // frequency ratio of successive octaves
  float gain = 0.5f;        // amplitude ratio of successive octaves
  uint64_t seed = 0;
  float baseFrequency = 4.0f;  // lattice cells per unit of tile coordinate at octave 0
  // Round each octave's cell count to an integer >= 1 and wrap the lattice there: that count is the
  // octave's period in lattice cells, so the sum tiles over [0, 1)^2.
  bool periodic = true;
  // Only octaves firstOctave .. octaves - 1 of that sum (each with the frequency, weight and
  // lattice hash it has in the whole sum), so that one fBm can be split into band-limited relief
  // levels whose heights add up to it exactly (Becker & Max 1993 section 4.3;
  // relief.split_octaves).
  int firstOctave = 0;
};

// Sum over octaves o of gain^o * noise(p * f_o), f_o = baseFrequency * lacunarity^o, where noise is
// Perlin-style gradient noise (a hashed unit gradient, one of 1024 directions, per lattice point;
// quintic fade 6t^5 - 15t^4 + 10t^3). Each octave has its own lattice hash. Deterministic per seed;
// one octave lies in about [-0.7, 0.7]. gradient() is exact (the fade's derivative is
// 30t^2 (t - 1)^2), not a finite difference.
class FractalNoise : public HeightSource {
 public:
  explicit FractalNoise(const FractalNoiseOptions& options);
  // Periodic, with integer baseFrequency: the form the scene files use.
  FractalNoise(int octaves, float lacunarity, float gain, uint64_t seed, int baseFrequency = 4);

  float height(Vec2 p) const override;
  Vec2 gradient(Vec2 p) const override;
  // Height and gradient in one pass (each octave's value comes with its gradient).
  float heightAndGradient(Vec2 p, Vec2& gradient) const override;
  // dir^T H dir with H the exact Hessian (the fade's second derivative is 60t (t - 1)(2t - 1)): one
  // pass, where differencing the gradient takes two.
  std::optional<float> secondDerivative(Vec2 p, Vec2 dir) const override;
  // The last octave's frequency: baseFrequency * lacunarity^(octaves - 1) (rounded when periodic).
  float highestFrequency() const override;
  // The lowest octave's frequency (of octaves firstOctave ..).
  float lowestFrequency() const override;
  uint64_t fingerprint() const override;
  // sum over octaves of |gain^o| times sqrt(2)/2, the largest value of 2D gradient noise with unit
  // gradients (reached only where all four corner gradients point at the sample).
  float maxAbsHeight() const override;

  const FractalNoiseOptions& options() const { return options_; }

 private:
  struct Octave {
    double frequency;  // lattice cells per unit of tile coordinate
    int period;        // lattice cells before the lattice repeats; 0 when not periodic
    float weight;
    uint64_t salt;
  };
  float octave(const Octave& o, Vec2 p, Vec2& grad) const;
  float octaveHeight(const Octave& o, Vec2 p) const;
  float octaveSecondDerivative(const Octave& o, Vec2 p, Vec2 dir) const;
  FractalNoiseOptions options_;
  std::vector<Octave> octaves_;
};

}  // namespace meso
