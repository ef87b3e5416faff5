// Whole frames of shipped scenes, in one run (issue 15's per-sample and per-frame ratios): per
// scene and resolution, the hybrid (auto) frame, the bump-mapped frame, full displacement at the
// default dicing, and the hybrid's own camera rays traced with Embree alone
// (RenderOptions::traceOnly, on the hybrid's geometry), and those rays with each hit's shadow rays
// (trace_all: every ray the shaded frame traces), and bump_trace_all: the same for the bump
// frame's own rays (its undisplaced geometry), so that each renderer's shading (with the limit
// surface at its hits) is its frame less its rays. Geometry and tables are prepared once per
// case, outside the timing; each iteration is renderFrame. Counters: micropolygons and samples;
// tools/bench prints the ratios hybrid / bump and hybrid / trace-only from them, and the shading
// ratio (hybrid - trace_all) / (bump - bump_trace_all). Run:
// ./build/tools/bench_frame [--benchmark_filter=default]
#include "meso/render/integrator.h"
#include "meso/render/render_context.h"
#include "meso/scene/scene_parser.h"

#include "bench_main.h"

#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>

namespace {

using namespace meso;

const std::filesystem::path kScenes = MESO_SCENES_DIR;

enum class Mode { Hybrid, Bump, Displacement, TraceOnly, TraceAll, BumpTraceAll };

struct Case {
  Case(const std::string& name, int width, int height, Algorithm algorithm)
      : scene(loadScene(kScenes / (name + ".toml"))) {
    scene.camera.width = width;
    scene.camera.height = height;
    scene.render.algorithm = algorithm;
    ctx.emplace(prepareRenderContext(scene, times, {.buildFrame = false}));
  }
  Scene scene;
  PrepareTimes times;
  std::optional<RenderContext> ctx;  // points at scene
  FrameGeometryStats geometry;
};

// One prepared case per (scene, resolution, geometry): trace-only shares the hybrid's geometry.
Case& prepared(const std::string& name, int width, int height, Algorithm algorithm) {
  static std::map<std::string, std::unique_ptr<Case>> cases;
  const std::string key =
      name + "/" + std::to_string(width) + "/" + std::to_string(static_cast<int>(algorithm));
  auto& c = cases[key];
  if (!c) {
    c = std::make_unique<Case>(name, width, height, algorithm);
    c->geometry = prepareFrame(*c->ctx, c->scene.camera, c->times);
  }
  return *c;
}

void BM_Frame(benchmark::State& state, const std::string& name, int width, int height, Mode mode) {
  const Algorithm algorithm = mode == Mode::Bump || mode == Mode::BumpTraceAll ? Algorithm::Bump
                              : mode == Mode::Displacement ? Algorithm::Displacement
                                                           : Algorithm::Auto;
  Case& c = prepared(name, width, height, algorithm);
  RenderOptions o;
  o.spp = c.scene.camera.spp;
  o.seed = c.scene.render.seed;
  o.progress = false;
  o.traceOnly = mode == Mode::TraceOnly || mode == Mode::TraceAll || mode == Mode::BumpTraceAll;
  o.traceShadowRays = mode == Mode::TraceAll || mode == Mode::BumpTraceAll;
  for (auto _ : state) {
    RenderCounters counters;
    benchmark::DoNotOptimize(renderFrame(*c.ctx, o, counters));
  }
  state.counters["micropolygons"] = static_cast<double>(c.geometry.micropolygons);
  state.counters["samples"] = static_cast<double>(width) * height * o.spp;
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(width) * height * o.spp);
}

const bool kRegistered = [] {
  const struct {
    const char* scene;
    int width, height;
  } frames[] = {{"default", 640, 360}, {"default", 1280, 720}, {"terrain", 640, 360}};
  const struct {
    const char* name;
    Mode mode;
  } modes[] = {{"hybrid", Mode::Hybrid},
               {"bump", Mode::Bump},
               {"displacement", Mode::Displacement},
               {"trace_only", Mode::TraceOnly},
               {"trace_all", Mode::TraceAll},
               {"bump_trace_all", Mode::BumpTraceAll}};
  for (const auto& f : frames)
    for (const auto& m : modes)
      benchmark::RegisterBenchmark(
          (std::string("BM_Frame/") + f.scene + "/" + std::to_string(f.width) + "x" +
           std::to_string(f.height) + "/" + m.name)
              .c_str(),
          BM_Frame, std::string(f.scene), f.width, f.height, m.mode)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->MinTime(0.5);
  return true;
}();

}  // namespace

MESO_BENCHMARK_MAIN()
