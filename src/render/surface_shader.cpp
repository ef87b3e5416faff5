#include "meso/render/surface_shader.h"

#include "meso/render/shading.h"

namespace meso {

ShadeResult shadeSurface(const RenderContext& ctx, const PreparedObject& object, const SurfacePoint& sp,
                         const Vec3& V) {
  ShadeResult r;
  // Shade the side that faces the eye (open meshes such as a ground plane are seen from either side).
  r.normal = glm::dot(sp.N, V) < 0.0f ? -sp.N : sp.N;
  r.colour = shadeLocal(ctx.scene->materials[object.material], ctx.scene->lights, sp.P, r.normal, V);
  r.algorithm = algorithm_colour::kSmooth;
  return r;
}

}  // namespace meso
