// Environment lighting by importance-sampled directional lights (docs/environment.md): the
// piecewise-constant 2-D distribution of pbrt's infinite area light, over a latitude-longitude map.
#include "meso/render/environment_map.h"

#include "meso/core/error.h"
#include "meso/core/piecewise_cdf.h"
#include "meso/core/rng.h"
#include "meso/core/texture_lookup.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace meso {
namespace {

// The shortest rotation taking +y to `up` (unit), after a turn of `degrees` about +y.
Mat3 mapToWorld(const Vec3& up, float degrees) {
  const Mat3 turn(glm::rotate(Mat4(1.0f), radians(degrees), Vec3(0.0f, 1.0f, 0.0f)));
  const Vec3 y(0.0f, 1.0f, 0.0f);
  const float c = glm::dot(y, up);
  if (c > 1.0f - 1e-7f) return turn;
  if (c < -1.0f + 1e-7f) return Mat3(glm::rotate(Mat4(1.0f), kPi, Vec3(1.0f, 0.0f, 0.0f))) * turn;
  const Vec3 axis = glm::normalize(glm::cross(y, up));
  return Mat3(glm::rotate(Mat4(1.0f), std::acos(c), axis)) * turn;
}

// Points of a (0, 2)-sequence in base 2: the radical inverse of i, and Sobol's second dimension.
uint32_t vanDerCorput(uint32_t i) {
  i = (i << 16) | (i >> 16);
  i = ((i & 0x00ff00ffu) << 8) | ((i & 0xff00ff00u) >> 8);
  i = ((i & 0x0f0f0f0fu) << 4) | ((i & 0xf0f0f0f0u) >> 4);
  i = ((i & 0x33333333u) << 2) | ((i & 0xccccccccu) >> 2);
  return ((i & 0x55555555u) << 1) | ((i & 0xaaaaaaaau) >> 1);
}

uint32_t sobolSecond(uint32_t i) {
  uint32_t r = 0;
  for (uint32_t v = 1u << 31; i; i >>= 1, v ^= v >> 1)
    if (i & 1u) r ^= v;
  return r;
}

float unitFloat(uint32_t bits) { return static_cast<float>(bits >> 8) * 0x1.0p-24f; }

}  // namespace

EnvironmentMap EnvironmentMap::load(const EnvironmentDecl& decl, uint64_t memoryLimitBytes) {
  if (decl.file.empty()) {
    Image one(1, 1, {"R", "G", "B"});
    for (int k = 0; k < 3; ++k) one.at(0, 0, k) = 1.0f;
    return EnvironmentMap(one, decl);
  }
  try {
    return EnvironmentMap(
        readColourImage(decl.file, decl.space, "environment maps", memoryLimitBytes).rgb, decl);
  } catch (const Error& e) {
    throw Error(decl.loc, "lights.environment", e.what());
  }
}

EnvironmentMap::EnvironmentMap(const Image& rgb, const EnvironmentDecl& decl)
    : width_(std::max(rgb.width, 1)),
      height_(std::max(rgb.height, 1)),
      toWorld_(mapToWorld(decl.up, decl.rotation)) {
  const size_t w = static_cast<size_t>(width_), h = static_cast<size_t>(height_);
  texels_.assign(w * h, Vec3(0.0f));
  std::vector<double> masses(w * h, 0.0);
  std::vector<double> rowMasses(h, 0.0);
  double total = 0.0;
  for (size_t y = 0; y < h && rgb.width > 0; ++y) {
    // Each texel's share of the sphere is its solid angle, sin(theta) at its centre times the
    // constant du dv.
    const double sinTheta = std::sin(kPi * (static_cast<double>(y) + 0.5) / static_cast<double>(h));
    for (size_t x = 0; x < w; ++x) {
      const Vec3 L = Vec3(rgb.at(static_cast<int>(x), static_cast<int>(y), 0),
                          rgb.at(static_cast<int>(x), static_cast<int>(y), 1),
                          rgb.at(static_cast<int>(x), static_cast<int>(y), 2)) *
                     decl.colour * decl.intensity;
      texels_[y * w + x] = L;
      masses[y * w + x] = std::max(0.0, static_cast<double>(luminance(L)) * sinTheta);
      rowMasses[y] += masses[y * w + x];
    }
    total += rowMasses[y];
  }
  black_ = !(total > 0.0) || !std::isfinite(total);
  density_.assign(w * h, 0.0f);
  if (!black_)
    for (size_t i = 0; i < w * h; ++i)
      density_[i] = static_cast<float>(masses[i] / total * static_cast<double>(w * h));
  appendCumulative(std::span<const double>(rowMasses), marginal_);
  for (size_t y = 0; y < h; ++y)
    appendCumulative(std::span<const double>(masses).subspan(y * w, w), rows_);
}

Vec3 EnvironmentMap::direction(Vec2 uv) const {
  const float theta = kPi * uv.y, phi = 2.0f * kPi * uv.x - kPi;
  const float s = std::sin(theta);
  return toWorld_ * Vec3(s * std::sin(phi), std::cos(theta), -s * std::cos(phi));
}

Vec2 EnvironmentMap::mapCoordinates(const Vec3& w) const {
  const Vec3 d = glm::transpose(toWorld_) * w;
  const float theta = std::acos(std::clamp(d.y, -1.0f, 1.0f));
  const float phi = std::atan2(d.x, -d.z);
  return {(phi + kPi) / (2.0f * kPi), theta / kPi};
}

size_t EnvironmentMap::texelOf(Vec2 uv) const {
  const int x = std::clamp(static_cast<int>(uv.x * static_cast<float>(width_)), 0, width_ - 1);
  const int y = std::clamp(static_cast<int>(uv.y * static_cast<float>(height_)), 0, height_ - 1);
  return static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x);
}

EnvironmentMap::Sample EnvironmentMap::sample(Vec2 xi) const {
  Sample s;
  if (black_) return s;
  const size_t w = static_cast<size_t>(width_);
  const BinPosition row = cdfInverseInBins(CdfRows(marginal_), xi.y, InverseSide::Lower);
  const BinPosition column =
      cdfInverseInBins(CdfRows(std::span<const float>(rows_).subspan(row.bin * (w + 1), w + 1)),
                       xi.x, InverseSide::Lower);
  const Vec2 uv(column.t() / static_cast<float>(width_), row.t() / static_cast<float>(height_));
  s.w = direction(uv);
  const float sinTheta = std::sin(kPi * uv.y);
  const size_t texel = row.bin * w + column.bin;
  if (!(sinTheta > 0.0f)) return s;  // a pole: no solid angle
  s.radiance = texels_[texel];
  s.pdf = density_[texel] / (2.0f * kPi * kPi * sinTheta);
  return s;
}

Vec3 EnvironmentMap::radiance(const Vec3& w) const { return texels_[texelOf(mapCoordinates(w))]; }

float EnvironmentMap::pdf(const Vec3& w) const {
  if (black_) return 0.0f;
  const Vec2 uv = mapCoordinates(w);
  const float sinTheta = std::sin(kPi * uv.y);
  return sinTheta > 0.0f ? density_[texelOf(uv)] / (2.0f * kPi * kPi * sinTheta) : 0.0f;
}

void environmentLights(const EnvironmentMap& env, uint64_t key, std::span<Light> lights) {
  const float n = static_cast<float>(lights.size());
  const uint32_t scrambleX = static_cast<uint32_t>(key),
                 scrambleY = static_cast<uint32_t>(key >> 32);
  for (size_t i = 0; i < lights.size(); ++i) {
    const uint32_t index = static_cast<uint32_t>(i);
    const EnvironmentMap::Sample s = env.sample(Vec2(unitFloat(vanDerCorput(index) ^ scrambleX),
                                                     unitFloat(sobolSecond(index) ^ scrambleY)));
    Light& l = lights[i];
    l = Light{};
    l.type = LightType::Directional;
    l.direction = -s.w;
    l.intensity = 1.0f;
    l.colour = s.pdf > 0.0f && std::isfinite(s.pdf) ? s.radiance / (s.pdf * n) : Vec3(0.0f);
  }
}

uint64_t environmentSampleKey(Vec2 film, uint64_t seed) {
  uint32_t x, y;
  std::memcpy(&x, &film.x, sizeof x);
  std::memcpy(&y, &film.y, sizeof y);
  return mix64(seed ^ mix64((static_cast<uint64_t>(x) << 32 | y) ^ 0x656e7669726f6eull));
}

}  // namespace meso
