#include "meso/render/render_context.h"

#include "meso/core/timer.h"
#include "meso/scene/mesh_io.h"

namespace meso {

RenderContext prepareRenderContext(const Scene& scene, PrepareTimes& times) {
  RenderContext ctx{&scene, Camera(scene.camera), {}, std::make_unique<RayScene>()};
  for (const Object& object : scene.objects) {
    Timer load;
    ControlMesh mesh = loadControlMesh(object.mesh);
    transformControlMesh(mesh, object.transform);
    times.load += load.seconds();

    Timer tess;
    LimitSurface surface(mesh, object.scheme);
    TessellatedMesh triangles = tessellateUniform(surface, scene.render.tessellationRate);
    times.tessellate += tess.seconds();

    Timer bvh;
    ctx.rays->addMesh(triangles);
    times.bvh += bvh.seconds();
    ctx.objects.push_back(PreparedObject{std::move(surface), std::move(triangles), object.material});
  }
  Timer bvh;
  ctx.rays->commit();
  times.bvh += bvh.seconds();
  return ctx;
}

}  // namespace meso
