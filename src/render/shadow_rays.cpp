// Macro shadows by Embree occlusion rays (DESIGN.md section 6; Becker & Max 1993, section 4.2).
#include "meso/render/shadow_rays.h"

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

bool shadowRay(const Light& light, const Vec3& start, Ray& ray) {
  ray = Ray{};
  ray.origin = start;
  if (light.type == LightType::Directional) {
    ray.direction = -light.direction;
    return true;
  }
  const Vec3 toLight = light.position - start;
  const float d = glm::length(toLight);
  if (!(d > 0.0f) || !std::isfinite(d)) return false;
  ray.direction = toLight / d;
  ray.tFar = d * (1.0f - 1e-5f);  // stop short of the light itself
  return true;
}

}  // namespace meso
