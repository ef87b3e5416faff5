// Kautz et al. 2001, sections 3.3 and 5.1: distance-dependent turbulence (fractal gradient noise)
// evaluated twice for the two random numbers (r1, r2), with octaves added smoothly as one zooms in.
#pragma once

#include "meso/core/math.h"

#include <array>
#include <cstdint>

namespace meso {

struct TurbulenceOptions {
  float baseFrequency = 8.0f;  // lattice cells per unit of the surface parameter at octave 0
  float lacunarity = 2.0f;     // frequency ratio of successive octaves (> 1)
  float gain = 0.5f;           // amplitude ratio of successive octaves (0 < gain <= 1)
  int maxOctaves = 12;         // the count never exceeds this (1..kMaxOctaves)
  // Octave o starts to fade in when its wavelength 1 / f_o spans this many pixels (the Nyquist
  // limit, 2) and is fully in one lacunarity step later.
  float nyquistPixels = 2.0f;
  uint64_t seed = 0;
};

// Two decorrelated fBm channels of 2D gradient noise (Perlin 1985, quintic fade; unit gradients
// from 256 evenly spaced directions, so each octave lies in [-sqrt(2)/2, sqrt(2)/2] and its value
// distribution is symmetric). Each channel and octave has its own lattice hash, random offset and
// random rotation, so the two channels are independent and octaves do not share lattice points.
//
// Fractional octave count (the level of detail):
//   c = clamp(log_lacunarity(pixelsPerUnit / (nyquistPixels * baseFrequency)), 0, maxOctaves),
// where pixelsPerUnit is how many pixels one unit of the surface parameter spans at the sample
// (1 / footprint). Octave o, of frequency f_o = baseFrequency * lacunarity^o, has the C1 weight
//   w_o(c) = s(clamp(c - o, 0, 1)),  s(x) = 3x^2 - 2x^3,
// so it fades in while its wavelength shrinks from lacunarity * nyquistPixels to nyquistPixels
// pixels, with zero slope at both ends (no popping). Each channel is
//   t(p, c) = (w_0 n_0(p) + sum_{o>=1} w_o gain^o n_o(p)) / sqrt(1 + sum_{o>=1} (w_o gain^o)^2),
// the weighted sum over its standard-deviation scale: once octave 0 is in (c >= 1) the spread of
// t barely changes with c (the paper's assumption; TurbulenceCdf tabulates what is left), and below
// c = 1 the first octave fades from t = 0, which L maps to its median normal (no detail).
// t is C1 in c and |dt/dc| <= 3.2.
// Deterministic per seed; evaluate() is allocation-free and thread-safe (the object is immutable).
class Turbulence {
 public:
  static constexpr int kMaxOctaves = 24;

  explicit Turbulence(const TurbulenceOptions& options);
  Turbulence() : Turbulence(TurbulenceOptions{}) {}

  // c from the projected frequency: pixels per unit of the surface parameter at the sample.
  // Non-finite or non-positive input gives 0.
  float octaveCount(float pixelsPerUnit) const;
  // w_o(c).
  static float octaveWeight(float c, int o);
  // (t1, t2) at p (units of the surface parameter) for octave count c (clamped to [0, maxOctaves]).
  Vec2 evaluate(Vec2 p, float c) const;
  // evaluate(p, octaveCount(pixelsPerUnit)).
  Vec2 atFootprint(Vec2 p, float pixelsPerUnit) const {
    return evaluate(p, octaveCount(pixelsPerUnit));
  }
  // One channel's octave o alone at p: gradient noise n_o(p) in [-0.7072, 0.7072].
  float octaveNoise(int channel, int o, Vec2 p) const;
  // An upper bound of |t| over all p and c.
  float maxAbs() const { return maxAbs_; }

  const TurbulenceOptions& options() const { return options_; }
  uint64_t fingerprint() const;

 private:
  struct Octave {
    double frequency;
    float amplitude;          // gain^o (1 for o = 0)
    float cosA, sinA;         // the lattice rotation
    double offsetX, offsetY;  // in lattice cells
    uint64_t salt;
  };
  TurbulenceOptions options_;
  float logLacunarity_;
  float maxAbs_;
  std::array<std::array<Octave, kMaxOctaves>, 2> octaves_;
  std::array<Vec2, 256> gradients_;
};

}  // namespace meso
