// Becker & Max 1993, section 6 of DESIGN.md: the local model I = ka + sum kd (L.N) + ks (H.N)^n.
#pragma once

#include "meso/core/math.h"
#include "meso/relief/slope_covariance.h"
#include "meso/scene/scene.h"

#include <array>
#include <span>

namespace meso {

// Direction towards the light and the light's incident intensity (colour * intensity, with 1/r^2
// falloff for point lights) at P.
struct LightSample {
  Vec3 L{0.0f, 0.0f, 1.0f};
  Vec3 radiance{0.0f};
};

LightSample sampleLight(const Light& light, const Vec3& P);

// How much of one light reaches a shading point (DESIGN.md section 6): the macro visibility of a
// shadow ray (0 or 1) times the relief's tabulated self-shadowing (ShadowingTable), separately for
// the diffuse and the specular term since the lit part of a relief faces the light more than the
// whole. {1, 1}: unshadowed.
struct LightShadow {
  float diffuse = 1.0f;
  float specular = 1.0f;
};

// Shadowing is tracked for this many lights of a camera sample (the scene's lights, then its
// environment's light samples); any further lights are unshadowed.
inline constexpr int kMaxShadowedLights = kMaxSampleLights;

// One factor per light (index as in the sample's lights, the first kMaxShadowedLights of them).
struct LightShadows {
  std::array<LightShadow, kMaxShadowedLights> light{};
  const LightShadow& operator[](size_t i) const {
    static constexpr LightShadow kLit{};
    return i < light.size() ? light[i] : kLit;
  }
  // This shadowing times another's (e.g. the macro shadows times a level's self-shadowing).
  LightShadows& operator*=(const LightShadows& o) {
    for (size_t i = 0; i < light.size(); ++i) {
      light[i].diffuse *= o.light[i].diffuse;
      light[i].specular *= o.light[i].specular;
    }
    return *this;
  }
};

// Reflected intensity towards V (unit, pointing from P to the eye) for a surface with shading
// normal N (unit). The ambient term is ka under unit white ambient light. Lights below the shading
// horizon (L.N <= 0) contribute nothing. `shadows` (may be null: all lit) scales each light's
// diffuse and specular terms; null gives exactly the unshadowed value.
Vec3 shadeLocal(const Reflectance& material, std::span<const Light> lights, const Vec3& P,
                const Vec3& N, const Vec3& V, const LightShadows* shadows = nullptr);

// The same with Schilling's roughness-modified highlight (his Appendix A): the highlight of a
// surface whose normal offsets, in the orthonormal tangent basis (e1, e2) of N, have the extra
// covariance `roughness` that filtering removed. With m = phong, the base factor K0 = I makes
// (cos^2 alpha')^(m / 2) exactly (H.N)^phong; the filtered covariance widens the equivalent
// Gaussian slope distribution (whose covariance is K / m), so K = I + phong * roughness. Unlike
// Schilling's, the lobe is scaled by 1 / sqrt(det K) so that its integral over slopes (the mean
// intensity of the footprint) does not grow as it widens. roughness = 0 gives shadeLocal's value
// up to float rounding.
Vec3 shadeRoughened(const Reflectance& material, std::span<const Light> lights, const Vec3& P,
                    const Vec3& N, const Vec3& V, const Vec3& e1, const Vec3& e2,
                    const SlopeCovariance& roughness, const LightShadows* shadows = nullptr);

}  // namespace meso
