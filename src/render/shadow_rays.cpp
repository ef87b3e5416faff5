// Macro shadows by Embree occlusion rays (DESIGN.md section 6; Becker & Max 1993, section 4.2).
#include "meso/render/shadow_rays.h"

#include "meso/core/rng.h"

#include <cstring>

#include <algorithm>
#include <cmath>

namespace meso {

float shadowOffset(const ShadowOrigin& o) {
  const float extent = std::max({std::abs(o.hit.x), std::abs(o.hit.y), std::abs(o.hit.z)});
  return 3e-5f * (1.0f + extent + std::abs(o.rayT));
}

Vec3 shadowRayStart(const ShadowOrigin& o) {
  Vec3 n = o.facetN;
  if (glm::dot(n, o.V) < 0.0f) n = -n;
  Vec3 start = o.hit;
  if (o.limitP) {
    const float bulge = glm::dot(*o.limitP - o.hit, n);
    if (bulge > 0.0f && std::isfinite(bulge)) start += bulge * n;
  }
  return start + shadowOffset(o) * n;
}

bool shadowRay(const Light& light, const Vec3& start, Ray& ray, Vec2 xi) {
  ray = Ray{};
  ray.origin = start;
  if (light.type == LightType::Directional) {
    ray.direction = -light.direction;
    return true;
  }
  const Vec3 toLight = light.position - start;
  const float d = glm::length(toLight);
  if (!(d > 0.0f) || !std::isfinite(d)) return false;
  const Vec3 axis = toLight / d;
  if (!(light.radius > 0.0f)) {
    ray.direction = axis;
    ray.tFar = d * (1.0f - 1e-5f);  // stop short of the light itself
    return true;
  }
  if (!(d > light.radius)) return false;  // inside the sphere: it sees the light
  // Uniform in the cone of half-angle asin(r / d) about the axis.
  const float sin2Max = (light.radius / d) * (light.radius / d);
  const float cosMax = std::sqrt(std::max(0.0f, 1.0f - sin2Max));
  const float cosTheta = 1.0f - xi.x * (1.0f - cosMax);
  const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
  const float phi = 2.0f * kPi * xi.y;
  const Vec3 e1 = glm::normalize(
      glm::cross(axis, std::abs(axis.x) < 0.9f ? Vec3(1.0f, 0.0f, 0.0f) : Vec3(0.0f, 1.0f, 0.0f)));
  const Vec3 e2 = glm::cross(axis, e1);
  ray.direction =
      glm::normalize(cosTheta * axis + sinTheta * (std::cos(phi) * e1 + std::sin(phi) * e2));
  // The nearer intersection with the sphere: t = d cos - sqrt(r^2 - d^2 sin^2).
  const float c = glm::dot(ray.direction, toLight);
  const float disc = light.radius * light.radius - (d * d - c * c);
  ray.tFar = (c - std::sqrt(std::max(disc, 0.0f))) * (1.0f - 1e-5f);
  return true;
}

Vec2 shadowSample(Vec2 film, size_t light, uint64_t seed) {
  uint32_t x, y;
  std::memcpy(&x, &film.x, sizeof x);
  std::memcpy(&y, &film.y, sizeof y);
  const uint64_t h = mix64(seed ^ mix64((static_cast<uint64_t>(x) << 32 | y) + light * 0x9e37ull));
  return Vec2(static_cast<float>(h >> 40) / 16777216.0f,
              static_cast<float>((h >> 16) & 0xffffff) / 16777216.0f);
}

}  // namespace meso
