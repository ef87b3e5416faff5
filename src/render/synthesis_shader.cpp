// Kautz, Heidrich & Seidel 2001, sections 4 and 5.1, with the consistency rule of
// appearance/synthesis_level.h.
#include "meso/render/synthesis_shader.h"

#include "meso/render/shading.h"
#include "meso/synthesis/synthesized_shading.h"

#include <algorithm>
#include <cmath>

namespace meso {
namespace {

float smoothstep01(float x) {
  x = std::clamp(x, 0.0f, 1.0f);
  return x * x * (3.0f - 2.0f * x);
}

}  // namespace

Vec3 synthesizedNormal(const SynthesisLevel& level, Vec2 uv, float c) {
  if (!level.index) return level.sampler->normalAtCount(uv, c);
  const float amplitude = smoothstep01(c);
  if (!(amplitude > 0.0f)) return Vec3(0.0f, 0.0f, 1.0f);
  const Vec2 tile = level.indexScale * uv;
  const Vec3 n0 = level.sampler->table().lookup(level.index->index(tile));
  const Vec3 n1 = level.index->normal(*level.sampler, tile, amplitude, c);
  return glm::normalize(toMicrofacetFrame(n0, n1));
}

SynthesisShade shadeSynthesisLevel(const SynthesisLevel& level, const Reflectance& material,
                                   std::span<const Light> lights, const Vec3& P, const Vec3& Pu,
                                   const Vec3& N, const Vec3& V, Vec2 uv, float pixelsPerUnit,
                                   const LightShadows* shadows) {
  SynthesisShade out;
  const float c = level.sampler->turbulence().octaveCount(pixelsPerUnit);
  out.weight = smoothstep01(c);
  const Vec3 m = synthesizedNormal(level, uv, c);
  // The NDF's x axis: P_u turned by the declared angle about N.
  Vec3 t = Pu - glm::dot(Pu, N) * N;
  const float len = glm::length(t);
  t = len > 1e-20f && std::isfinite(len) ? t / len : Vec3(0.0f);
  const Vec3 T = level.cosAngle * t + level.sinAngle * glm::cross(N, t);
  const ScaledSlopeNdf lobe(
      *level.ndf, std::sqrt(std::max(1.0f - kStructureShare * out.weight * out.weight, 1e-4f)));
  out.normal = ndfFrameToWorld(N, T, m);
  out.colour = material.ka;
  for (size_t i = 0; i < lights.size(); ++i) {
    const LightShadow shadow = shadows ? (*shadows)[i] : LightShadow{};
    if (shadows && shadow.diffuse <= 0.0f && shadow.specular <= 0.0f) continue;
    const LightSample s = sampleLight(lights[i], P);
    const SynthesizedShading f = shadeSynthesized(lobe, N, T, V, s.L, m);
    const float diffuse =
        level.lambert ? f.diffuse : std::max(glm::dot(s.L, N), 0.0f) * (glm::dot(V, N) > 0.0f);
    // Multiplying by exactly 1 keeps the unshadowed bits.
    out.colour += s.radiance * (material.kd * (diffuse * shadow.diffuse) +
                                material.ks * ((f.specular / level.peak) * shadow.specular));
  }
  return out;
}

}  // namespace meso
