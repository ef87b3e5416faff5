// Becker & Max 1993, section 2.2 (quadratic bump derivatives, eq. 3 and eq. 4).
#include "meso/relief/height_source.h"

#include "meso/core/error.h"
#include "meso/core/hash.h"
#include "meso/core/image_io.h"
#include "meso/core/rng.h"

#include <algorithm>
#include <cmath>

namespace meso {
namespace {

int wrapIndex(int i, int n) {
  const int m = i % n;
  return m < 0 ? m + n : m;
}

// The paper's weights: the derivative of the uniform cubic B-spline over B[i-1..i+2] at fraction d.
inline void quadraticWeights(float d, float w[4]) {
  const float d2 = d * d;
  w[0] = -0.5f * d2 + d - 0.5f;
  w[1] = 1.5f * d2 - 2.0f * d;
  w[2] = -1.5f * d2 + d + 0.5f;
  w[3] = 0.5f * d2;
}

}  // namespace

HeightTable::HeightTable(int width, int height, std::vector<float> texels, bool periodic,
                         BumpDerivativeMethod method)
    : width_(width), height_(height), texels_(std::move(texels)), periodic_(periodic), method_(method) {
  if (width_ <= 0 || height_ <= 0 || texels_.size() != static_cast<size_t>(width_) * height_)
    throw Error("height table: expected width x height texels, got " + std::to_string(width_) + " x " +
                std::to_string(height_) + " with " + std::to_string(texels_.size()) + " values");
}

HeightTable HeightTable::fromImage(const Image& image, const std::filesystem::path& file, bool periodic) {
  if (image.width <= 0 || image.height <= 0)
    throw Error(file.string() + ": height image has zero size (" + std::to_string(image.width) + "x" +
                std::to_string(image.height) + ")");
  const int c = image.numChannels();
  if (c == 2 || c < 1 || c > 4)
    throw Error(file.string() + ": height image must have 1 channel (or RGB/RGBA, whose luminance is used), got " +
                std::to_string(c) + " channels");
  std::vector<float> texels(static_cast<size_t>(image.width) * image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const float v = c == 1 ? image.at(x, y, 0)
                             : 0.2126f * image.at(x, y, 0) + 0.7152f * image.at(x, y, 1) + 0.0722f * image.at(x, y, 2);
      if (!std::isfinite(v)) throw Error(file.string() + ": height image has a NaN or infinite texel at (" +
                                         std::to_string(x) + ", " + std::to_string(y) + ")");
      // Image rows go top to bottom; v grows upwards.
      texels[static_cast<size_t>(image.height - 1 - y) * image.width + x] = v;
    }
  return HeightTable(image.width, image.height, std::move(texels), periodic);
}

HeightTable HeightTable::load(const std::filesystem::path& file, bool periodic) {
  return fromImage(readImage(file), file, periodic);
}

float HeightTable::texel(int i, int j) const {
  i = periodic_ ? wrapIndex(i, width_) : std::clamp(i, 0, width_ - 1);
  j = periodic_ ? wrapIndex(j, height_) : std::clamp(j, 0, height_ - 1);
  return texels_[static_cast<size_t>(j) * width_ + i];
}

float HeightTable::rowLerp(int i, float ty) const {
  const float f = std::floor(ty);
  const int j = static_cast<int>(f);
  const float w = ty - f;
  return (1.0f - w) * texel(i, j) + w * texel(i, j + 1);
}

float HeightTable::colLerp(int j, float tx) const {
  const float f = std::floor(tx);
  const int i = static_cast<int>(f);
  const float w = tx - f;
  return (1.0f - w) * texel(i, j) + w * texel(i + 1, j);
}

float HeightTable::height(Vec2 p) const {
  const float tx = p.x * width_ - 0.5f, ty = p.y * height_ - 0.5f;
  const float fy = std::floor(ty);
  const float w = ty - fy;
  return (1.0f - w) * colLerp(static_cast<int>(fy), tx) + w * colLerp(static_cast<int>(fy) + 1, tx);
}

Vec2 HeightTable::gradient(Vec2 p) const {
  if (!std::isfinite(p.x) || !std::isfinite(p.y)) return Vec2(0.0f);
  const float tx = p.x * width_ - 0.5f, ty = p.y * height_ - 0.5f;
  if (method_ == BumpDerivativeMethod::CentralDifference) {
    const float e = 1.0f;  // one texel: the eight neighbours of eq. (3)
    const Vec2 dx(e / width_, 0.0f), dy(0.0f, e / height_);
    return {(height(p + dx) - height(p - dx)) * width_ / (2.0f * e),
            (height(p + dy) - height(p - dy)) * height_ / (2.0f * e)};
  }
  const float fx = std::floor(tx), fy = std::floor(ty);
  const int i = static_cast<int>(fx), j = static_cast<int>(fy);
  float wx[4], wy[4];
  quadraticWeights(tx - fx, wx);
  quadraticWeights(ty - fy, wy);
  float du = 0.0f, dv = 0.0f;
  for (int k = 0; k < 4; ++k) {
    du += wx[k] * rowLerp(i - 1 + k, ty);  // linear in v
    dv += wy[k] * colLerp(j - 1 + k, tx);  // linear in u
  }
  return {du * width_, dv * height_};  // per texel -> per tile
}

float HeightTable::highestFrequency() const { return 0.5f * static_cast<float>(std::min(width_, height_)); }

uint64_t HeightTable::fingerprint() const {
  return Hasher().string("HeightTable").value(width_).value(height_).value(periodic_).value(method_)
      .bytes(texels_.data(), texels_.size() * sizeof(float)).digest();
}

FractalNoise::FractalNoise(int octaves, float lacunarity, float gain, uint64_t seed, int baseFrequency) : seed_(seed) {
  float f = static_cast<float>(baseFrequency), a = 1.0f;
  for (int o = 0; o < std::max(octaves, 1); ++o) {
    cells_.push_back(std::max(1, static_cast<int>(std::lround(f))));
    weights_.push_back(a);
    f *= lacunarity;
    a *= gain;
  }
}

float FractalNoise::octave(Vec2 p, int cells, uint64_t salt, Vec2& grad) const {
  const float x = p.x * cells, y = p.y * cells;
  const float fx = std::floor(x), fy = std::floor(y);
  const int ix = static_cast<int>(fx), iy = static_cast<int>(fy);
  const float u = x - fx, v = y - fy;
  const auto fade = [](float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); };
  const auto dfade = [](float t) { return 30.0f * t * t * (t * (t - 2.0f) + 1.0f); };
  float n[4];
  Vec2 g[4];
  for (int c = 0; c < 4; ++c) {
    const int cx = wrapIndex(ix + (c & 1), cells), cy = wrapIndex(iy + (c >> 1), cells);
    const uint64_t h = mix64(seed_ ^ mix64(salt ^ (static_cast<uint64_t>(cx) << 32 | static_cast<uint32_t>(cy))));
    const float angle = static_cast<float>(h >> 40) * (2.0f * kPi / 16777216.0f);
    g[c] = Vec2(std::cos(angle), std::sin(angle));
    n[c] = glm::dot(g[c], Vec2(u - (c & 1), v - (c >> 1)));
  }
  const float su = fade(u), sv = fade(v), dsu = dfade(u), dsv = dfade(v);
  const float nx0 = n[0] + su * (n[1] - n[0]), nx1 = n[2] + su * (n[3] - n[2]);
  const float value = nx0 + sv * (nx1 - nx0);
  // d/du and d/dv of the bilinear blend of the corner ramps (each ramp's own gradient is g[c]).
  const Vec2 gx0 = g[0] + su * (g[1] - g[0]) + Vec2(dsu * (n[1] - n[0]), 0.0f);
  const Vec2 gx1 = g[2] + su * (g[3] - g[2]) + Vec2(dsu * (n[3] - n[2]), 0.0f);
  const Vec2 gv = gx0 + sv * (gx1 - gx0) + Vec2(0.0f, dsv * (nx1 - nx0));
  grad = gv * static_cast<float>(cells);
  return value;
}

float FractalNoise::height(Vec2 p) const {
  float h = 0.0f;
  Vec2 g;
  for (size_t o = 0; o < cells_.size(); ++o) h += weights_[o] * octave(p, cells_[o], o, g);
  return h;
}

Vec2 FractalNoise::gradient(Vec2 p) const {
  Vec2 total(0.0f), g;
  for (size_t o = 0; o < cells_.size(); ++o) {
    octave(p, cells_[o], o, g);
    total += weights_[o] * g;
  }
  return total;
}

float FractalNoise::highestFrequency() const { return static_cast<float>(cells_.back()); }

uint64_t FractalNoise::fingerprint() const {
  Hasher h;
  h.string("FractalNoise").value(seed_);
  for (size_t o = 0; o < cells_.size(); ++o) h.value(cells_[o]).value(weights_[o]);
  return h.digest();
}

Vec3 blinnNormal(const Vec3& Pu, const Vec3& Pv, const Vec3& N, float Bu, float Bv) {
  const Vec3 area = glm::cross(Pu, Pv);
  // P' = P + h N: P'_u x P'_v = Pu x Pv + Bu (N x Pv) - Bv (N x Pu) to first order (eq. 4).
  Vec3 n = area + Bu * glm::cross(N, Pv) - Bv * glm::cross(N, Pu);
  if (glm::dot(area, N) < 0.0f) n = -n;  // mirrored parameterization: keep facing like N
  const float len = glm::length(n);
  return len > 1e-30f && std::isfinite(len) ? n / len : N;
}

}  // namespace meso
