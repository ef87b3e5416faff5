// Becker & Max 1993, section 2 and DESIGN.md section 6: ka + sum kd (L.N) + ks (H.N)^n.
#include "meso/render/shading.h"

#include <algorithm>
#include <cmath>

namespace meso {

LightSample sampleLight(const Light& light, const Vec3& P) {
  LightSample s;
  if (light.type == LightType::Directional) {
    s.L = -light.direction;
    s.radiance = light.colour * light.intensity;
    return s;
  }
  const Vec3 toLight = light.position - P;
  // A point light touching the surface would divide by zero: clamp the distance to a tiny value.
  const float r2 = std::max(glm::dot(toLight, toLight), 1e-12f);
  s.L = toLight / std::sqrt(r2);
  s.radiance = light.colour * (light.intensity / r2);
  return s;
}

Vec3 shadeLocal(const Material& material, std::span<const Light> lights, const Vec3& P,
                const Vec3& N, const Vec3& V) {
  Vec3 I = material.ka;
  for (const Light& light : lights) {
    const LightSample s = sampleLight(light, P);
    const float LdotN = glm::dot(s.L, N);
    if (LdotN <= 0.0f) continue;
    Vec3 reflect = material.kd * LdotN;
    if (material.ks != Vec3(0.0f)) {
      const Vec3 h = s.L + V;
      const float len = glm::length(h);
      // L = -V (light exactly behind the eye direction) has no half vector: no highlight.
      const float HdotN = len > 1e-12f ? std::max(glm::dot(h / len, N), 0.0f) : 0.0f;
      reflect += material.ks * std::pow(HdotN, material.phong);
    }
    I += reflect * s.radiance;
  }
  return I;
}

}  // namespace meso
