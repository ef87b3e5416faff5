// Becker & Max 1993, end of section 3: Perlin's volume textures (solid_noise.h).
#include "meso/relief/solid_noise.h"

#include "meso/core/error.h"
#include "meso/core/hash.h"
#include "meso/core/rng.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

namespace meso {
namespace {

inline float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
inline float fadeDerivative(float t) { return 30.0f * t * t * (t * (t - 2.0f) + 1.0f); }

// 3 Q: the lattice rotation's integer form (symmetric, M M = 9 I).
constexpr int kM[3][3] = {{1, 2, 2}, {2, 1, -2}, {2, -2, 1}};

Vec3 rotate(Vec3 q) {
  return Vec3(kM[0][0] * q.x + kM[0][1] * q.y + kM[0][2] * q.z,
              kM[1][0] * q.x + kM[1][1] * q.y + kM[1][2] * q.z,
              kM[2][0] * q.x + kM[2][1] * q.y + kM[2][2] * q.z) /
         3.0f;
}

// 4096 unit gradients spread evenly over the sphere (a Fibonacci lattice).
const std::array<Vec3, 4096>& gradientTable() {
  static const std::array<Vec3, 4096> table = [] {
    std::array<Vec3, 4096> t;
    const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
    for (size_t k = 0; k < t.size(); ++k) {
      const double z = 1.0 - (2.0 * static_cast<double>(k) + 1.0) / static_cast<double>(t.size());
      const double r = std::sqrt(std::max(0.0, 1.0 - z * z)), a = golden * static_cast<double>(k);
      t[k] = Vec3(static_cast<float>(r * std::cos(a)), static_cast<float>(r * std::sin(a)),
                  static_cast<float>(z));
    }
    return t;
  }();
  return table;
}

inline int64_t floorDiv(int64_t a, int64_t b) {
  const int64_t q = a / b;
  return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
}

// The lattice point c reduced modulo the periods of an octave of frequency f, p M Z^3 with
// p = f period / 3 (a shift of q by `period` along an axis moves the lattice by one of them): one
// representative per class, found from c's coordinates M c / (9 p) in that basis.
inline void reduce(int64_t c[3], int f, int period) {
  const int64_t p = static_cast<int64_t>(f) * (period / 3);
  int64_t m[3];
  for (int k = 0; k < 3; ++k)
    m[k] = floorDiv(kM[k][0] * c[0] + kM[k][1] * c[1] + kM[k][2] * c[2], 9 * p);
  for (int k = 0; k < 3; ++k) c[k] -= p * (kM[k][0] * m[0] + kM[k][1] * m[1] + kM[k][2] * m[2]);
}

inline Vec3 latticeGradient(int64_t cx, int64_t cy, int64_t cz, uint64_t salt) {
  const uint64_t key = static_cast<uint64_t>(cx) * 0x9e3779b97f4a7c15ull +
                       static_cast<uint64_t>(cy) * 0xc2b2ae3d27d4eb4full +
                       static_cast<uint64_t>(cz) * 0x165667b19e3779f9ull;
  return gradientTable()[mix64(salt ^ key) >> 52];
}

}  // namespace

int solidTilePeriod(const SolidNoiseOptions& o) {
  double f = 1.0;
  for (int k = 1; k < o.octaves; ++k) f *= o.lacunarity;
  const double finest = std::max(1.0, std::round(f));
  return std::max(3, 3 * static_cast<int>(std::floor(kSolidTileCycles / (3.0 * finest))));
}

SolidNoise::SolidNoise(const SolidNoiseOptions& options)
    : options_(options), period_(options.period > 0 ? options.period : solidTilePeriod(options)) {
  if (period_ % 3 != 0)
    throw Error("solid noise: the period must be a multiple of 3 (got " + std::to_string(period_) +
                ")");
  if (options.octaves < 1 || options.octaves > 24 || options.firstOctave < 0 ||
      options.firstOctave >= options.octaves || !(options.lacunarity >= 1.0f) ||
      !std::isfinite(options.lacunarity) || !std::isfinite(options.gain))
    throw Error(
        "solid noise: need 1..24 octaves, a first octave below them and a finite "
        "lacunarity >= 1 (got " +
        std::to_string(options.octaves) + " octaves from " + std::to_string(options.firstOctave) +
        ", lacunarity " + std::to_string(options.lacunarity) + ")");
  double f = 1.0, a = 1.0;
  for (int o = 0; o < options.octaves; ++o) {
    Octave oct;
    oct.frequency = static_cast<int>(std::clamp(std::round(f), 1.0, 1e6));
    oct.weight = static_cast<float>(a);
    oct.salt = mix64(options.seed ^ mix64(static_cast<uint64_t>(o) + 0x5011d0015eedull));
    const uint64_t s = mix64(oct.salt + 1);
    oct.offset = Vec3(static_cast<float>(s & 0xfffff), static_cast<float>((s >> 20) & 0xfffff),
                      static_cast<float>((s >> 40) & 0xfffff)) /
                 1048576.0f;
    if (o >= options.firstOctave) octaves_.push_back(oct);
    f *= options.lacunarity;
    a *= options.gain;
  }
}

// Perlin gradient noise at lattice point x = Q f q + c: corner k contributes g_k . (x - k),
// blended by the quintic fade in each axis; the gradient with respect to q is f Q^T grad_x.
float SolidNoise::octave(const Octave& o, Vec3 q, Vec3* grad) const {
  const Vec3 r = rotate(q);
  double x[3] = {static_cast<double>(r.x) * o.frequency + o.offset.x,
                 static_cast<double>(r.y) * o.frequency + o.offset.y,
                 static_cast<double>(r.z) * o.frequency + o.offset.z};
  int64_t cell[3];
  float t[3];
  for (int k = 0; k < 3; ++k) {
    if (!(std::abs(x[k]) < 1e12)) x[k] = std::isfinite(x[k]) ? std::fmod(x[k], 1e12) : 0.0;
    const double fl = std::floor(x[k]);
    cell[k] = static_cast<int64_t>(fl);
    t[k] = static_cast<float>(x[k] - fl);
  }
  float n[8];
  Vec3 g[8];
  for (int k = 0; k < 8; ++k) {
    int64_t c[3] = {cell[0] + (k & 1), cell[1] + ((k >> 1) & 1), cell[2] + (k >> 2)};
    if (options_.periodic) reduce(c, o.frequency, period_);
    g[k] = latticeGradient(c[0], c[1], c[2], o.salt);
    n[k] = glm::dot(g[k],
                    Vec3(t[0] - static_cast<float>(k & 1), t[1] - static_cast<float>((k >> 1) & 1),
                         t[2] - static_cast<float>(k >> 2)));
  }
  const float s[3] = {fade(t[0]), fade(t[1]), fade(t[2])};
  // Trilinear blend of the corner ramps: along x, then y, then z.
  float nx[4];
  for (int k = 0; k < 4; ++k) nx[k] = n[2 * k] + s[0] * (n[2 * k + 1] - n[2 * k]);
  const float ny0 = nx[0] + s[1] * (nx[1] - nx[0]), ny1 = nx[2] + s[1] * (nx[3] - nx[2]);
  const float value = ny0 + s[2] * (ny1 - ny0);
  if (grad) {
    // Product rule: each ramp's own gradient is g_k, the fades add ds/dt times the differences.
    const float d[3] = {fadeDerivative(t[0]), fadeDerivative(t[1]), fadeDerivative(t[2])};
    Vec3 gx[4];
    for (int k = 0; k < 4; ++k)
      gx[k] = g[2 * k] + s[0] * (g[2 * k + 1] - g[2 * k]) +
              Vec3(d[0] * (n[2 * k + 1] - n[2 * k]), 0.0f, 0.0f);
    const Vec3 gy0 = gx[0] + s[1] * (gx[1] - gx[0]) + Vec3(0.0f, d[1] * (nx[1] - nx[0]), 0.0f);
    const Vec3 gy1 = gx[2] + s[1] * (gx[3] - gx[2]) + Vec3(0.0f, d[1] * (nx[3] - nx[2]), 0.0f);
    const Vec3 gl = gy0 + s[2] * (gy1 - gy0) + Vec3(0.0f, 0.0f, d[2] * (ny1 - ny0));
    *grad = rotate(gl) * static_cast<float>(o.frequency);  // Q is symmetric: Q^T = Q
  }
  return value;
}

float SolidNoise::heightAndGradient(Vec3 q, Vec3& gradient) const {
  float h = 0.0f;
  gradient = Vec3(0.0f);
  for (const Octave& o : octaves_) {
    Vec3 g;
    h += o.weight * octave(o, q, &g);
    gradient += o.weight * g;
  }
  return h;
}

float SolidNoise::height(Vec3 q) const {
  Vec3 g;
  return heightAndGradient(q, g);
}

Vec3 SolidNoise::gradient(Vec3 q) const {
  Vec3 g;
  heightAndGradient(q, g);
  return g;
}

float SolidNoise::highestFrequency() const { return static_cast<float>(octaves_.back().frequency); }

float SolidNoise::lowestFrequency() const {
  double lowest = octaves_.front().frequency;
  for (const Octave& o : octaves_) lowest = std::min(lowest, static_cast<double>(o.frequency));
  return static_cast<float>(lowest);
}

float SolidNoise::maxAbsHeight() const {
  double sum = 0.0;
  for (const Octave& o : octaves_) sum += std::abs(static_cast<double>(o.weight));
  return static_cast<float>(sum * 0.86602540378443865 * (1.0 + 1e-5));
}

uint64_t SolidNoise::fingerprint() const {
  Hasher h;
  h.string("SolidNoise/1").value(options_.seed).value(options_.periodic);
  if (options_.periodic) h.value(period_);
  for (const Octave& o : octaves_) h.value(o.frequency).value(o.weight).value(o.salt);
  return h.digest();
}

namespace {

bool isPeriod(Vec3 v, int period) {
  for (int k = 0; k < 3; ++k) {
    const float cells = v[k] / static_cast<float>(period);
    if (std::abs(cells - std::round(cells)) > 1e-4f) return false;
  }
  return true;
}

SolidNoiseOptions periodicOptions(SolidNoiseOptions o) {
  o.periodic = true;
  return o;
}

}  // namespace

SolidSlice::SolidSlice(SolidNoiseOptions noise, Vec3 a, Vec3 b, float side)
    : noise_(periodicOptions(noise)),
      a_(a),
      b_(b),
      side_(side > 0.0f ? side : static_cast<float>(noise_.period())) {
  const int period = noise_.period();
  if (std::abs(glm::length(a) - 1.0f) > 1e-5f || std::abs(glm::length(b) - 1.0f) > 1e-5f ||
      std::abs(glm::dot(a, b)) > 1e-5f || !isPeriod(side_ * a, period) ||
      !isPeriod(side_ * b, period))
    throw Error("solid slice: the tile's axes must be orthonormal and side times each a period (" +
                std::to_string(period) + " along x, y and z)");
}

float SolidSlice::height(Vec2 p) const { return noise_.height(side_ * (p.x * a_ + p.y * b_)); }

float SolidSlice::heightAndGradient(Vec2 p, Vec2& g) const {
  Vec3 g3;
  const float h = noise_.heightAndGradient(side_ * (p.x * a_ + p.y * b_), g3);
  g = side_ * Vec2(glm::dot(g3, a_), glm::dot(g3, b_));
  return h;
}

Vec2 SolidSlice::gradient(Vec2 p) const {
  Vec2 g;
  heightAndGradient(p, g);
  return g;
}

float SolidSlice::highestFrequency() const { return side_ * noise_.highestFrequency(); }

uint64_t SolidSlice::fingerprint() const {
  Hasher h;
  h.string("SolidSlice/1").value(noise_.fingerprint()).value(a_).value(b_).value(side_);
  return h.digest();
}

}  // namespace meso
