// Becker & Max 1993, section 2.2 (Perlin's noise as heights): fBm with analytic gradients.
#include "meso/relief/fractal_noise.h"

#include "meso/core/check.h"
#include "meso/core/error.h"
#include "meso/core/hash.h"
#include "meso/core/rng.h"
#include "meso/relief/height_table.h"  // floorFast

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

namespace meso {
namespace {

inline float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
inline float fadeDerivative(float t) { return 30.0f * t * t * (t * (t - 2.0f) + 1.0f); }
inline float fadeSecondDerivative(float t) { return 60.0f * t * ((t - 1.0f) * (2.0f * t - 1.0f)); }

// Lattice cell (wrapped when periodic) and fraction of a point along one axis.
inline void lattice(float p, double frequency, int period, int64_t& cell, float& t) {
  double x = static_cast<double>(p) * frequency;
  if (!(std::abs(x) < 1e9)) {  // huge or not finite: keep the cell index in range (the hash wraps)
    x = std::isfinite(x) ? std::fmod(x, period > 0 ? period : 4294967296.0) : 0.0;
    if (period > 0) x -= period * floorFast(x / period);
  } else if (period > 0) {
    // Exact on the lattice: tiles bit for bit. A periodic octave's frequency is its period (below
    // 2^27), so x = p * period is exact in double (24 + 27 bits) and floor(x / period) is floor(p).
    MESO_DCHECK(frequency == period, "a periodic octave's frequency is its period");
    x -= period * floorFast(static_cast<double>(p));
  }
  const double f = floorFast(x);
  cell = static_cast<int64_t>(f);
  t = static_cast<float>(x - f);
}

// 1024 unit gradients evenly spread in angle: a table lookup instead of a sincos per corner.
const std::array<Vec2, 1024>& gradientTable() {
  static const std::array<Vec2, 1024> table = [] {
    std::array<Vec2, 1024> t;
    for (size_t k = 0; k < t.size(); ++k) {
      const double a = 2.0 * std::numbers::pi * (static_cast<double>(k) + 0.5) / t.size();
      t[k] = Vec2(static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)));
    }
    return t;
  }();
  return table;
}

inline int64_t wrapCell(int64_t c, int period) {
  return period > 0 && c >= period ? c - period : c;
}

// The lattice cell of p at one octave: p's position (u, v) in it and the hashed unit gradients of
// its corners, corner c at (c & 1, c >> 1).
struct Cell {
  float u, v;
  Vec2 g[4];
  // Corner c's ramp g_c . (p - corner_c).
  float ramp(int c) const {
    return glm::dot(g[c], Vec2(u - static_cast<float>(c & 1), v - static_cast<float>(c >> 1)));
  }
};

inline Cell cellAt(Vec2 p, double frequency, int period, uint64_t salt) {
  Cell cell;
  int64_t ix, iy;
  lattice(p.x, frequency, period, ix, cell.u);
  lattice(p.y, frequency, period, iy, cell.v);
  const std::array<Vec2, 1024>& gradients = gradientTable();
  for (int c = 0; c < 4; ++c) {
    const uint64_t cx = static_cast<uint64_t>(wrapCell(ix + (c & 1), period));
    const uint64_t cy = static_cast<uint32_t>(wrapCell(iy + (c >> 1), period));
    cell.g[c] = gradients[mix64(salt ^ (cx << 32 | cy)) >> 54];
  }
  return cell;
}

}  // namespace

FractalNoise::FractalNoise(const FractalNoiseOptions& options) : options_(options) {
  if (options.octaves < 1 || options.octaves > 24 || options.firstOctave < 0 ||
      options.firstOctave >= options.octaves || !(options.lacunarity > 0.0f) ||
      !std::isfinite(options.gain) || !(options.baseFrequency > 0.0f) ||
      !std::isfinite(options.lacunarity * options.baseFrequency))
    throw Error(
        "fractal noise: need 1..24 octaves, a first octave below them and positive finite "
        "lacunarity and base frequency (got " +
        std::to_string(options.octaves) + " octaves from " + std::to_string(options.firstOctave) +
        ", lacunarity " + std::to_string(options.lacunarity) + ", base frequency " +
        std::to_string(options.baseFrequency) + ")");
  double f = options.baseFrequency, a = 1.0;
  for (int o = 0; o < options.octaves; ++o) {
    Octave oct;
    oct.period = options.periodic ? static_cast<int>(std::clamp(std::round(f), 1.0, 1e8)) : 0;
    oct.frequency = options.periodic ? oct.period : f;
    oct.weight = static_cast<float>(a);
    oct.salt = mix64(options.seed ^ mix64(static_cast<uint64_t>(o) +
                                          0x9e3779b97f4a7c15ull));  // per seed and octave
    if (o >= options.firstOctave) octaves_.push_back(oct);
    f *= options.lacunarity;
    a *= options.gain;
  }
}

FractalNoise::FractalNoise(int octaves, float lacunarity, float gain, uint64_t seed,
                           int baseFrequency)
    : FractalNoise(FractalNoiseOptions{std::max(octaves, 1), lacunarity, gain, seed,
                                       static_cast<float>(baseFrequency), true}) {}

// Perlin gradient noise: corner c contributes g_c . (p - corner_c), blended by the quintic fade.
[[gnu::always_inline]] inline float FractalNoise::octave(const Octave& o, Vec2 p,
                                                         Vec2& grad) const {
  const Cell cell = cellAt(p, o.frequency, o.period, o.salt);
  const Vec2* g = cell.g;
  const float n[4] = {cell.ramp(0), cell.ramp(1), cell.ramp(2), cell.ramp(3)};
  const float u = cell.u, v = cell.v;
  const float su = fade(u), sv = fade(v), dsu = fadeDerivative(u), dsv = fadeDerivative(v);
  const float nx0 = n[0] + su * (n[1] - n[0]), nx1 = n[2] + su * (n[3] - n[2]);
  // Product rule on the bilinear blend of the corner ramps (each ramp's own gradient is g[c]).
  const Vec2 gx0 = g[0] + su * (g[1] - g[0]) + Vec2(dsu * (n[1] - n[0]), 0.0f);
  const Vec2 gx1 = g[2] + su * (g[3] - g[2]) + Vec2(dsu * (n[3] - n[2]), 0.0f);
  grad = (gx0 + sv * (gx1 - gx0) + Vec2(0.0f, dsv * (nx1 - nx0))) * static_cast<float>(o.frequency);
  return nx0 + sv * (nx1 - nx0);
}

// octave() without the gradient: the same value, bit for bit (the same operations in the same
// order).
[[gnu::always_inline]] inline float FractalNoise::octaveHeight(const Octave& o, Vec2 p) const {
  const Cell cell = cellAt(p, o.frequency, o.period, o.salt);
  const float n[4] = {cell.ramp(0), cell.ramp(1), cell.ramp(2), cell.ramp(3)};
  const float su = fade(cell.u), sv = fade(cell.v);
  const float nx0 = n[0] + su * (n[1] - n[0]), nx1 = n[2] + su * (n[3] - n[2]);
  return nx0 + sv * (nx1 - nx0);
}

// octave()'s second derivative along dir (in tile units): with A = n0 + su (n1 - n0) and
// C = n2 + su (n3 - n2) the blends along u, the octave is A + sv (C - A), each ramp n_c linear.
[[gnu::always_inline]] inline float FractalNoise::octaveSecondDerivative(const Octave& o, Vec2 p,
                                                                         Vec2 dir) const {
  const Cell cell = cellAt(p, o.frequency, o.period, o.salt);
  const Vec2* g = cell.g;
  const float n[4] = {cell.ramp(0), cell.ramp(1), cell.ramp(2), cell.ramp(3)};
  const float u = cell.u, v = cell.v;
  const float su = fade(u), sv = fade(v), dsu = fadeDerivative(u), dsv = fadeDerivative(v);
  const float ddsu = fadeSecondDerivative(u), ddsv = fadeSecondDerivative(v);
  const float A = n[0] + su * (n[1] - n[0]), C = n[2] + su * (n[3] - n[2]);
  const Vec2 dA = g[0] + su * (g[1] - g[0]) + Vec2(dsu * (n[1] - n[0]), 0.0f);
  const Vec2 dC = g[2] + su * (g[3] - g[2]) + Vec2(dsu * (n[3] - n[2]), 0.0f);
  const float Auu = 2.0f * dsu * (g[1].x - g[0].x) + ddsu * (n[1] - n[0]);
  const float Cuu = 2.0f * dsu * (g[3].x - g[2].x) + ddsu * (n[3] - n[2]);
  const float Auv = dsu * (g[1].y - g[0].y), Cuv = dsu * (g[3].y - g[2].y);
  const float uu = Auu + sv * (Cuu - Auu);
  const float uv = Auv + dsv * (dC.x - dA.x) + sv * (Cuv - Auv);
  const float vv = ddsv * (C - A) + 2.0f * dsv * (dC.y - dA.y);
  const float f = static_cast<float>(o.frequency);
  return (f * f) * (dir.x * dir.x * uu + 2.0f * dir.x * dir.y * uv + dir.y * dir.y * vv);
}

std::optional<float> FractalNoise::secondDerivative(Vec2 p, Vec2 dir) const {
  float d2 = 0.0f;
  for (const Octave& o : octaves_) d2 += o.weight * octaveSecondDerivative(o, p, dir);
  return d2;
}

float FractalNoise::heightAndGradient(Vec2 p, Vec2& gradient) const {
  float h = 0.0f;
  gradient = Vec2(0.0f);
  for (const Octave& o : octaves_) {
    Vec2 g;
    h += o.weight * octave(o, p, g);
    gradient += o.weight * g;
  }
  return h;
}

float FractalNoise::height(Vec2 p) const {
  float h = 0.0f;
  for (const Octave& o : octaves_) h += o.weight * octaveHeight(o, p);
  return h;
}

Vec2 FractalNoise::gradient(Vec2 p) const {
  Vec2 g;
  heightAndGradient(p, g);
  return g;
}

float FractalNoise::highestFrequency() const {
  return static_cast<float>(octaves_.back().frequency);
}

float FractalNoise::lowestFrequency() const {
  double lowest = octaves_.front().frequency;
  for (const Octave& o : octaves_) lowest = std::min(lowest, static_cast<double>(o.frequency));
  return static_cast<float>(lowest);
}

uint64_t FractalNoise::fingerprint() const {
  Hasher h;
  h.string("FractalNoise/2").value(options_.seed);  // /2: the lattice hash of this version
  if (options_.firstOctave > 0) h.value(options_.firstOctave);  // whole sums keep their keys
  for (const Octave& o : octaves_) h.value(o.frequency).value(o.period).value(o.weight);
  return h.digest();
}

}  // namespace meso

namespace meso {

float FractalNoise::maxAbsHeight() const {
  double sum = 0.0;
  for (const Octave& o : octaves_) sum += std::abs(static_cast<double>(o.weight));
  return static_cast<float>(sum * 0.70710678118654752 * (1.0 + 1e-5));
}

}  // namespace meso
