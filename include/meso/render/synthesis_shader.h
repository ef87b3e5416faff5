// Kautz, Heidrich & Seidel 2001, sections 4 and 5.1: a material's synthesis level shaded at one
// sample, with the consistency rule of appearance/synthesis_level.h.
#pragma once

#include "meso/appearance/synthesis_level.h"
#include "meso/render/shading.h"
#include "meso/scene/scene.h"

#include <span>

namespace meso {

// What synthesis did at one point.
struct SynthesisShade {
  Vec3 colour{0.0f};
  Vec3 normal{0.0f, 0.0f, 1.0f};  // the synthesized normal (world)
  float weight = 0.0f;            // w0: how much synthesized detail is in (0 far, 1 near)
};

// The synthesized normal in the NDF's frame at uv with octave count c. With an index texture, the
// detail added to the finest level's own normal n0 = L(index): L(index + noise) expressed in n0's
// frame, z (no change) until the first octave fades in.
Vec3 synthesizedNormal(const SynthesisLevel& level, Vec2 uv, float c);

// Shades a surface point whose frame is (Pu, N) (N unit, facing the eye), at surface parameters uv,
// seen from V (unit, towards the eye) with pixelsPerUnit pixels per unit of u:
// ka + sum over lights of radiance (kd (L.n_m) + ks D_lobe(h in n_m's frame) / peak), each light's
// terms scaled by `shadows` (may be null: all lit).
SynthesisShade shadeSynthesisLevel(const SynthesisLevel& level, const Reflectance& material,
                                   std::span<const Light> lights, const Vec3& P, const Vec3& Pu,
                                   const Vec3& N, const Vec3& V, Vec2 uv, float pixelsPerUnit,
                                   const LightShadows* shadows = nullptr);

}  // namespace meso
