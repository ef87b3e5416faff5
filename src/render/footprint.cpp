// The footprint of a pixel in (u, v) (surface_shader.h), for filtered bump and texture lookups.
#include "meso/render/surface_shader.h"

#include <cmath>

namespace meso {

Footprint footprintAt(const SurfacePoint& sp, const Ray& rx, const Ray& ry, float scale) {
  Footprint fp;
  const float a = glm::dot(sp.Pu, sp.Pu), b = glm::dot(sp.Pu, sp.Pv), c = glm::dot(sp.Pv, sp.Pv);
  const float det = a * c - b * b;
  if (!(det > 1e-20f * a * c) || !std::isfinite(det)) return fp;
  Vec2 d[2];
  const Ray* rays[2] = {&rx, &ry};
  for (int k = 0; k < 2; ++k) {
    const float denom = glm::dot(rays[k]->direction, sp.N);
    if (std::abs(denom) < 1e-8f) return fp;
    const float t = glm::dot(sp.P - rays[k]->origin, sp.N) / denom;
    if (!(t > 0.0f) || !std::isfinite(t)) return fp;
    const Vec3 dP = (rays[k]->origin + t * rays[k]->direction - sp.P) * scale;
    const float pu = glm::dot(sp.Pu, dP), pv = glm::dot(sp.Pv, dP);
    d[k] = Vec2(c * pu - b * pv, a * pv - b * pu) / det;
  }
  fp.dUVdx = d[0];
  fp.dUVdy = d[1];
  fp.valid = std::isfinite(d[0].x) && std::isfinite(d[0].y) && std::isfinite(d[1].x) &&
             std::isfinite(d[1].y);
  return fp;
}

Reflectance textureReflectance(const RenderContext& ctx, int material, Vec2 uv,
                               const Footprint& footprint) {
  Reflectance r = ctx.scene->materials[static_cast<size_t>(material)];
  const RenderContext::MaterialTextures& t = ctx.materialTextures[static_cast<size_t>(material)];
  const Vec2 dx = footprint.valid ? footprint.dUVdx : Vec2(0.0f);
  const Vec2 dy = footprint.valid ? footprint.dUVdy : Vec2(0.0f);
  if (t.kd >= 0) r.kd = ctx.textures->rgb(t.kd, uv, dx, dy);
  if (t.ks >= 0) r.ks = ctx.textures->rgb(t.ks, uv, dx, dy);
  return r;
}

}  // namespace meso
