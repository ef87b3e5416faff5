// Kautz et al. 2001, sections 3.3 and 5.1: turbulence with a fractional, smoothly blended octave
// count; Perlin 1985 / 2002 gradient noise with the quintic fade.
#include "meso/synthesis/turbulence.h"

#include "meso/core/error.h"
#include "meso/core/hash.h"
#include "meso/core/rng.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace meso {
namespace {

inline float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }

}  // namespace

Turbulence::Turbulence(const TurbulenceOptions& options) : options_(options) {
  const TurbulenceOptions& o = options;
  if (!(o.baseFrequency > 0.0f) || !std::isfinite(o.baseFrequency) || !(o.lacunarity > 1.0f) ||
      !std::isfinite(o.lacunarity) || !(o.gain > 0.0f) || !(o.gain <= 1.0f) || o.maxOctaves < 1 ||
      o.maxOctaves > kMaxOctaves || !(o.nyquistPixels > 0.0f) || !std::isfinite(o.nyquistPixels)) {
    std::ostringstream s;
    s << "turbulence: need base frequency > 0, lacunarity > 1, 0 < gain <= 1, 1.." << kMaxOctaves
      << " octaves and nyquist pixels > 0 (got " << o.baseFrequency << ", " << o.lacunarity << ", "
      << o.gain << ", " << o.maxOctaves << ", " << o.nyquistPixels << ")";
    throw Error(s.str());
  }
  logLacunarity_ = std::log(o.lacunarity);
  for (size_t k = 0; k < gradients_.size(); ++k) {
    const double a = 2.0 * std::numbers::pi * (static_cast<double>(k) + 0.5) / gradients_.size();
    gradients_[k] = Vec2(static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)));
  }
  double sumAbs = 0.0;
  for (int ch = 0; ch < 2; ++ch) {
    Rng rng(o.seed, 0x7475726275ull + ch);  // one stream per channel: independent r1 and r2
    double f = o.baseFrequency, a = 1.0;
    for (int k = 0; k < kMaxOctaves; ++k) {
      Octave& oct = octaves_[ch][k];
      oct.frequency = f;
      oct.amplitude = static_cast<float>(a);
      const double angle = 2.0 * std::numbers::pi * rng.uniform();
      oct.cosA = static_cast<float>(std::cos(angle));
      oct.sinA = static_cast<float>(std::sin(angle));
      oct.offsetX = 4096.0 * rng.uniform();
      oct.offsetY = 4096.0 * rng.uniform();
      oct.salt = mix64(
          o.seed ^ mix64(0x51ed270b + 977u * static_cast<uint64_t>(ch) + static_cast<uint64_t>(k)));
      if (ch == 0 && k < o.maxOctaves) sumAbs += a;
      f *= o.lacunarity;
      a *= o.gain;
    }
  }
  // |numerator| <= 0.7072 sum a_o, and the denominator is >= 1.
  maxAbs_ = static_cast<float>(0.70711 * sumAbs);
}

float Turbulence::octaveCount(float pixelsPerUnit) const {
  if (!(pixelsPerUnit > 0.0f) || !std::isfinite(pixelsPerUnit)) return 0.0f;
  const float c =
      std::log(pixelsPerUnit / (options_.nyquistPixels * options_.baseFrequency)) / logLacunarity_;
  return std::clamp(c, 0.0f, static_cast<float>(options_.maxOctaves));
}

float Turbulence::octaveWeight(float c, int o) {
  const float x = std::clamp(c - static_cast<float>(o), 0.0f, 1.0f);
  return x * x * (3.0f - 2.0f * x);
}

float Turbulence::octaveNoise(int channel, int o, Vec2 p) const {
  const Octave& oct = octaves_[channel & 1][std::clamp(o, 0, kMaxOctaves - 1)];
  // Rotate, scale and offset into the octave's lattice (double: high octaves have millions of
  // cells).
  const double x =
      (static_cast<double>(oct.cosA) * p.x - static_cast<double>(oct.sinA) * p.y) * oct.frequency +
      oct.offsetX;
  const double y =
      (static_cast<double>(oct.sinA) * p.x + static_cast<double>(oct.cosA) * p.y) * oct.frequency +
      oct.offsetY;
  const double fx = std::floor(x), fy = std::floor(y);
  const float u = static_cast<float>(x - fx), v = static_cast<float>(y - fy);
  const uint32_t ix = static_cast<uint32_t>(static_cast<int64_t>(fx)),
                 iy = static_cast<uint32_t>(static_cast<int64_t>(fy));
  const uint32_t salt = static_cast<uint32_t>(oct.salt);
  float n[4];
  for (int c = 0; c < 4; ++c) {
    // A 32-bit lattice hash (the lowbias32 finaliser of Wellons 2018): a quarter of mix64's cost.
    uint32_t h = (ix + (c & 1)) * 0x27d4eb2du ^ (iy + (c >> 1)) * 0x165667b1u ^ salt;
    h ^= h >> 16, h *= 0x7feb352du, h ^= h >> 15, h *= 0x846ca68bu, h ^= h >> 16;
    const Vec2 g = gradients_[h >> 24];
    n[c] = g.x * (u - static_cast<float>(c & 1)) + g.y * (v - static_cast<float>(c >> 1));
  }
  const float su = fade(u), sv = fade(v);
  const float a = n[0] + su * (n[1] - n[0]), b = n[2] + su * (n[3] - n[2]);
  return a + sv * (b - a);
}

Vec2 Turbulence::evaluate(Vec2 p, float c) const {
  if (!(c > 0.0f)) return Vec2(0.0f);  // also NaN
  c = std::min(c, static_cast<float>(options_.maxOctaves));
  const int count = std::min(static_cast<int>(std::ceil(c)), options_.maxOctaves);
  float t1 = 0.0f, t2 = 0.0f, spread = 1.0f;
  for (int o = 0; o < count; ++o) {
    const float w = octaveWeight(c, o) * octaves_[0][o].amplitude;
    t1 += w * octaveNoise(0, o, p);
    t2 += w * octaveNoise(1, o, p);
    if (o > 0) spread += w * w;
  }
  const float s = 1.0f / std::sqrt(spread);
  return Vec2(t1 * s, t2 * s);
}

uint64_t Turbulence::fingerprint() const {
  return Hasher()
      .string("Turbulence/1")
      .value(options_.baseFrequency)
      .value(options_.lacunarity)
      .value(options_.gain)
      .value(options_.maxOctaves)
      .value(options_.nyquistPixels)
      .value(options_.seed)
      .digest();
}

}  // namespace meso
