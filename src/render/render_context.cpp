#include "meso/render/render_context.h"

#include "meso/core/timer.h"
#include "meso/scene/mesh_io.h"

namespace meso {

Algorithm parseAlgorithm(const std::string& name) {
  if (name == "brdf") return Algorithm::Brdf;
  if (name == "bump") return Algorithm::Bump;
  if (name == "redistribution") return Algorithm::Redistribution;
  if (name == "displacement") return Algorithm::Displacement;
  return Algorithm::Auto;
}

RenderContext prepareRenderContext(const Scene& scene, PrepareTimes& times) {
  RenderContext ctx{&scene, Camera(scene.camera), {}, std::make_unique<RayScene>(), {}, {},
                    parseAlgorithm(scene.render.algorithm)};
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

  Timer tables;
  const TableCache cache(scene.render.cacheDir.empty() ? TableCache::defaultFolder() : scene.render.cacheDir);
  ctx.reliefs.resize(scene.materials.size());
  std::vector<bool> used(scene.materials.size(), false);
  for (const Object& o : scene.objects) used[o.material] = true;
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    if (!used[m] || scene.materials[m].relief.empty()) continue;
    ctx.reliefs[m] = buildMaterialRelief(scene.materials[m], cache, &ctx.warnings);
    times.tablesBuilt += ctx.reliefs[m].tablesBuilt;
    times.tablesFromCache += ctx.reliefs[m].tablesFromCache;
  }
  times.tables += tables.seconds();
  return ctx;
}

}  // namespace meso
