#include "render_command.h"

#include "meso/core/atomic_file.h"
#include "meso/core/error.h"
#include "meso/core/image_io.h"
#include "meso/core/timer.h"
#include "meso/render/integrator.h"
#include "meso/render/render_context.h"
#include "meso/scene/scene_parser.h"

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <cstdio>
#include <fstream>

namespace meso::app {
namespace {

const char* schemeName(SubdivisionScheme s) {
  switch (s) {
    case SubdivisionScheme::CatmullClark: return "catmull-clark";
    case SubdivisionScheme::Loop: return "loop";
    case SubdivisionScheme::Bilinear: return "bilinear";
  }
  return "?";
}

void applyOverrides(const RenderCommandOptions& o, Scene& scene) {
  if (o.spp) scene.camera.spp = *o.spp;
  if (o.threads) scene.render.threads = *o.threads;
  if (o.seed) scene.render.seed = *o.seed;
  if (o.algorithm) scene.render.algorithm = *o.algorithm;
  if (o.tessellationRate) scene.render.tessellationRate = *o.tessellationRate;
  if (o.width) scene.camera.width = *o.width;
  if (o.height) scene.camera.height = *o.height;
}

// Relief rendering (bump, redistribution, BRDF tables, displacement) is not in this version: say so
// instead of silently rendering something else.
void checkAlgorithm(const Scene& scene) {
  const std::string& a = scene.render.algorithm;
  if (a != "auto")
    throw Error(scene.file.string() + ": render.algorithm: '" + a +
                "' is not available in this version of meso (available: auto)");
  for (const Material& m : scene.materials)
    if (!m.relief.empty())
      std::fprintf(stderr, "meso: warning: %s: material '%s' declares relief levels; this version "
                           "shades the smooth limit surface only\n",
                   scene.file.string().c_str(), m.name.c_str());
}

nlohmann::json settingsJson(const Scene& scene, const std::filesystem::path& output) {
  const CameraSettings& c = scene.camera;
  nlohmann::json objects = nlohmann::json::array();
  for (const Object& o : scene.objects)
    objects.push_back({{"mesh", o.mesh.string()}, {"scheme", schemeName(o.scheme)},
                       {"material", scene.materials[o.material].name}});
  return {{"scene", scene.file.string()},
          {"output", output.string()},
          {"algorithm", scene.render.algorithm},
          {"seed", scene.render.seed},
          {"threads", scene.render.threads},
          {"tessellation_rate", scene.render.tessellationRate},
          {"width", c.width},
          {"height", c.height},
          {"spp", c.spp},
          {"fov", c.fovY},
          {"camera_position", {c.position.x, c.position.y, c.position.z}},
          {"camera_look_at", {c.lookAt.x, c.lookAt.y, c.lookAt.z}},
          {"lights", scene.lights.size()},
          {"objects", objects}};
}

void writeText(const std::filesystem::path& file, const std::string& text) {
  writeAtomically(file, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp);
    out << text << '\n';
    if (!out.flush()) throw Error(file.string() + ": cannot write");
  });
}

std::filesystem::path defaultOutput(const std::filesystem::path& scene) {
  return std::filesystem::path("out") / (scene.stem().string() + ".exr");
}

}  // namespace

void runRender(const RenderCommandOptions& o) {
  Timer total, phase;
  Scene scene = loadScene(o.scene);
  applyOverrides(o, scene);
  checkAlgorithm(scene);
  const std::filesystem::path output = o.output.empty() ? defaultOutput(o.scene) : o.output;
  if (output.extension() != ".exr")
    throw Error(output.string() + ": output must be an .exr file (the PNG preview is written beside it)");
  const double parseSeconds = phase.seconds();

  const int threads = scene.render.threads > 0 ? scene.render.threads : tbb::info::default_concurrency();
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);

  PrepareTimes prep;
  RenderContext ctx = prepareRenderContext(scene, prep);

  phase.reset();
  RenderCounters counters;
  RenderOptions ro{scene.camera.spp, scene.render.seed, !o.quiet, o.falseColour};
  Image film = renderFrame(ctx, ro, counters);
  const double renderSeconds = phase.seconds();

  phase.reset();
  if (!output.parent_path().empty()) std::filesystem::create_directories(output.parent_path());
  std::filesystem::path png = output;
  png.replace_extension(".png");
  writeExr(output, film);
  writePngPreview(png, film);
  const double writeSeconds = phase.seconds();

  if (!o.statsFile.empty()) {
    nlohmann::json stats = {
        {"seconds", {{"parse", parseSeconds + prep.load}, {"tessellate", prep.tessellate}, {"bvh", prep.bvh},
                     {"render", renderSeconds}, {"write", writeSeconds}, {"total", total.seconds()}}},
        {"peak_rss_mib", peakRssMib()},
        {"rays", counters.rays.load()},
        {"triangles", ctx.numTriangles()},
        {"settings", settingsJson(scene, output)}};
    stats["settings"]["threads_used"] = threads;
    writeText(o.statsFile, stats.dump(2));
  }
  if (!o.quiet)
    std::fprintf(stderr, "meso: wrote %s and %s (%dx%d, %d spp, %.2f s)\n", output.string().c_str(),
                 png.string().c_str(), film.width, film.height, scene.camera.spp, total.seconds());
}

}  // namespace meso::app
