// The --stats JSON of `meso render` (see render_stats.h).
#include "render_stats.h"

#include "meso/core/timer.h"

#include <cmath>

namespace meso::app {
namespace {

// Fractions of all samples per SampleRenderer (render/integrator.h).
nlohmann::json sampleShares(const RenderCounters& counters) {
  const double samples = static_cast<double>(counters.rays.load()) * kShareUnit;
  nlohmann::json shares = nlohmann::json::object();
  for (int k = 0; k < kSampleRenderers; ++k)
    shares[kSampleRendererNames[k]] =
        samples > 0.0 ? static_cast<double>(counters.shares[k].load()) / samples : 0.0;
  return shares;
}

nlohmann::json perMillion(double value, size_t micropolygons) {
  return micropolygons > 0 ? nlohmann::json(value) : nlohmann::json(nullptr);
}

}  // namespace

nlohmann::json settingsJson(const Scene& scene, const std::filesystem::path& output) {
  const CameraSettings& c = scene.camera;
  const TransitionSettings& t = scene.render.transition;
  nlohmann::json objects = nlohmann::json::array();
  for (const Object& o : scene.objects)
    objects.push_back({{"mesh", o.mesh.string()},
                       {"scheme", choiceName(o.scheme)},
                       {"material", scene.materials[o.material].name}});
  return {{"scene", scene.file.string()},
          {"output", output.string()},
          {"algorithm", choiceName(scene.render.algorithm)},
          {"seed", scene.render.seed},
          {"threads", scene.render.threads},
          {"tessellation_rate", scene.render.tessellationRate},
          {"dicing_rate", scene.render.dicingRate},
          {"dicing_metric", choiceName(scene.render.dicingMetric)},
          {"across_view_cap", scene.render.acrossViewCap},
          {"relief_samples", scene.render.reliefSamples},
          {"max_micropolygons", scene.render.maxMicropolygons},
          {"normals", choiceName(scene.render.normals)},
          {"shadows", scene.render.shadows},
          {"transition",
           {{"D", t.D}, {"eps", t.eps}, {"e1", t.e1}, {"e2", t.e2}, {"e3", t.e3}, {"e4", t.e4}}},
          {"width", c.width},
          {"height", c.height},
          {"spp", c.spp},
          {"fov", c.fovY},
          {"camera_position", {c.position.x, c.position.y, c.position.z}},
          {"camera_look_at", {c.lookAt.x, c.lookAt.y, c.lookAt.z}},
          {"lights", scene.lights.size()},
          {"environment_light_samples", scene.environment ? scene.render.lightSamples : 0},
          {"objects", objects}};
}

nlohmann::json frameJson(int frame, const std::filesystem::path& exr, int64_t rays,
                         size_t triangles, const FrameGeometryStats& geometry, double renderSeconds,
                         double writeSeconds) {
  return {{"frame", frame},
          {"output", exr.string()},
          {"rays", rays},
          {"triangles", triangles},
          {"micropolygons", geometry.micropolygons},
          {"micropolygons_off_screen", geometry.offScreenMicropolygons},
          {"faces_diced", geometry.facesDiced},
          {"dicing_coarsened_by", geometry.coarsening},
          {"dicing_coarsened_beyond", std::isfinite(geometry.coarsenedBeyond)
                                          ? nlohmann::json(geometry.coarsenedBeyond)
                                          : nlohmann::json(nullptr)},
          {"geometry_rebuilt", geometry.rebuilt},
          {"seconds",
           {{"tessellate", geometry.tessellateSeconds},
            {"bvh", geometry.bvhSeconds},
            {"render", renderSeconds},
            {"write", writeSeconds}}}};
}

nlohmann::json statsJson(const Scene& scene, const std::filesystem::path& output,
                         const RenderRunStats& run, const PrepareTimes& prep,
                         const RenderCounters& counters, const std::vector<std::string>& warnings) {
  const double peak = peakRssMib();
  const size_t mp = run.maxMicropolygons;
  nlohmann::json stats = {
      {"seconds",
       {{"parse", run.parseSeconds + prep.load},
        {"tessellate", prep.tessellate},
        {"bvh", prep.bvh},
        {"render", run.renderSeconds},
        {"write", run.writeSeconds},
        {"total", run.totalSeconds}}},
      {"peak_rss_mib", peak},
      {"rays", counters.rays.load()},
      {"sample_shares", sampleShares(counters)},
      {"non_finite_values", counters.nonFinite.load()},
      {"triangles", run.maxTriangles},
      {"micropolygons", mp},
      {"tessellate_seconds", prep.tessellate},
      {"bvh_seconds", prep.bvh},
      {"peak_mib_per_million_micropolygons",
       perMillion(peak / (static_cast<double>(mp) * 1e-6), mp)},
      {"geometry_mib_per_million_micropolygons", perMillion(run.geometryMibPerMillion, mp)},
      {"mesh_mib_per_million_micropolygons", perMillion(run.meshMibPerMillion, mp)},
      {"warnings", warnings},
      {"tables_built", prep.tablesBuilt},
      {"tables_from_cache", prep.tablesFromCache},
      {"tables_seconds", prep.tables},
      {"frames_rendered", run.rendered},
      {"frames_skipped", run.skipped},
      {"frames", run.perFrame},
      {"settings", settingsJson(scene, output)}};
  stats["settings"]["threads_used"] = run.threads;
  return stats;
}

}  // namespace meso::app
