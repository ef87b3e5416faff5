// Becker & Max 1993, section 2 and DESIGN.md section 6: ka + sum kd (L.N) + ks (H.N)^n.
#include "meso/render/shading.h"

#include "meso/relief/schilling_phong.h"

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

namespace {

// ka + sum over lights of radiance (kd (L.N) + ks highlight(H)), H the unit half vector; lights
// below the shading horizon add nothing, and L = -V (no half vector) has no highlight.
template <class Highlight>
Vec3 shadeWith(const Reflectance& material, std::span<const Light> lights, const Vec3& P,
               const Vec3& N, const Vec3& V, const LightShadows* shadows,
               const Highlight& highlight) {
  Vec3 I = material.ka;
  for (size_t i = 0; i < lights.size(); ++i) {
    // Without shadows the arithmetic is exactly the unshadowed model's (bit-identical images).
    const LightShadow shadow = shadows ? (*shadows)[i] : LightShadow{};
    if (shadows && shadow.diffuse <= 0.0f && shadow.specular <= 0.0f) continue;
    const LightSample s = sampleLight(lights[i], P);
    const float LdotN = glm::dot(s.L, N);
    if (LdotN <= 0.0f) continue;
    Vec3 reflect = shadows ? material.kd * (LdotN * shadow.diffuse) : material.kd * LdotN;
    if (material.ks != Vec3(0.0f)) {
      const Vec3 h = s.L + V;
      const float len = glm::length(h);
      if (len > 1e-12f)
        reflect += shadows ? material.ks * (highlight(h / len) * shadow.specular)
                           : material.ks * highlight(h / len);
    }
    I += reflect * s.radiance;
  }
  return I;
}

}  // namespace

Vec3 shadeLocal(const Reflectance& material, std::span<const Light> lights, const Vec3& P,
                const Vec3& N, const Vec3& V, const LightShadows* shadows) {
  return shadeWith(material, lights, P, N, V, shadows, [&](const Vec3& H) {
    return std::pow(std::max(glm::dot(H, N), 0.0f), material.phong);
  });
}

Vec3 shadeRoughened(const Reflectance& material, std::span<const Light> lights, const Vec3& P,
                    const Vec3& N, const Vec3& V, const Vec3& e1, const Vec3& e2,
                    const SlopeCovariance& roughness, const LightShadows* shadows) {
  const float m = std::max(material.phong, 1e-3f);
  const SlopeCovariance K = SlopeCovariance{1.0f, 0.0f, 1.0f} + m * roughness;
  const RoughnessFactor D = roughnessFactor(K);
  // Schilling's lobe only widens (its peak stays 1); meso keeps the lobe's integral over slopes,
  // 2 pi sqrt(det(K / m)), equal to the smooth one so that filtering preserves mean intensity.
  const float det = K.a * K.c - K.b * K.b;
  const float energy = det > 1.0f && std::isfinite(det) ? 1.0f / std::sqrt(det) : 1.0f;
  return shadeWith(material, lights, P, N, V, shadows, [&](const Vec3& H) {
    return energy * schillingSpecular(modifiedCos2Alpha(N, H, e1, e2, D), m);
  });
}

}  // namespace meso
