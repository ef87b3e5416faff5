// Becker & Max 1993, section 6 of DESIGN.md: the local model I = ka + sum kd (L.N) + ks (H.N)^n.
#pragma once

#include "meso/core/math.h"
#include "meso/scene/scene.h"

#include <span>

namespace meso {

// Direction towards the light and the light's incident intensity (colour * intensity, with 1/r^2
// falloff for point lights) at P.
struct LightSample {
  Vec3 L{0.0f, 0.0f, 1.0f};
  Vec3 radiance{0.0f};
};

LightSample sampleLight(const Light& light, const Vec3& P);

// Reflected intensity towards V (unit, pointing from P to the eye) for a surface with shading
// normal N (unit). The ambient term is ka under unit white ambient light. Lights below the shading
// horizon (L.N <= 0) contribute nothing; no shadows (relief self-shadowing is left out so that the
// renderers stay comparable, DESIGN.md section 6).
Vec3 shadeLocal(const Material& material, std::span<const Light> lights, const Vec3& P,
                const Vec3& N, const Vec3& V);

}  // namespace meso
