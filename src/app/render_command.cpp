#include "render_command.h"

#include "cli_values.h"
#include "external_program.h"
#include "memory_estimates.h"

#include "meso/core/atomic_file.h"
#include "meso/core/error.h"
#include "meso/core/image_io.h"
#include "meso/core/timer.h"
#include "meso/render/integrator.h"
#include "meso/render/render_context.h"
#include "meso/render/transition.h"
#include "meso/scene/camera_path.h"
#include "meso/scene/scene_parser.h"

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <thread>

#include <semaphore.h>
#include <unistd.h>

namespace meso::app {
namespace {

const char* schemeName(SubdivisionScheme s) {
  switch (s) {
    case SubdivisionScheme::CatmullClark:
      return "catmull-clark";
    case SubdivisionScheme::Loop:
      return "loop";
    case SubdivisionScheme::Bilinear:
      return "bilinear";
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
  if (o.dicingRate) scene.render.dicingRate = *o.dicingRate;
  if (o.dicingMetric) scene.render.dicingMetric = *o.dicingMetric;
  if (o.maxMicropolygons) scene.render.maxMicropolygons = *o.maxMicropolygons;
  if (o.normals) scene.render.normals = *o.normals;
  if (o.noShadows) scene.render.shadows = false;
  TransitionSettings& t = scene.render.transition;
  if (o.transitionD) t.D = *o.transitionD;
  if (o.transitionEps) t.eps = *o.transitionEps;
  if (o.thresholds.size() == 4)
    t.e1 = o.thresholds[0], t.e2 = o.thresholds[1], t.e3 = o.thresholds[2], t.e4 = o.thresholds[3];
  validateTransitionSettings(t, "--D/--eps/--thresholds");
}

nlohmann::json settingsJson(const Scene& scene, const std::filesystem::path& output) {
  const CameraSettings& c = scene.camera;
  nlohmann::json objects = nlohmann::json::array();
  for (const Object& o : scene.objects)
    objects.push_back({{"mesh", o.mesh.string()},
                       {"scheme", schemeName(o.scheme)},
                       {"material", scene.materials[o.material].name}});
  return {{"scene", scene.file.string()},
          {"output", output.string()},
          {"algorithm", scene.render.algorithm},
          {"seed", scene.render.seed},
          {"threads", scene.render.threads},
          {"tessellation_rate", scene.render.tessellationRate},
          {"dicing_rate", scene.render.dicingRate},
          {"dicing_metric", scene.render.dicingMetric},
          {"max_micropolygons", scene.render.maxMicropolygons},
          {"normals", scene.render.normals},
          {"shadows", scene.render.shadows},
          {"transition",
           {{"D", scene.render.transition.D},
            {"eps", scene.render.transition.eps},
            {"e1", scene.render.transition.e1},
            {"e2", scene.render.transition.e2},
            {"e3", scene.render.transition.e3},
            {"e4", scene.render.transition.e4}}},
          {"width", c.width},
          {"height", c.height},
          {"spp", c.spp},
          {"fov", c.fovY},
          {"camera_position", {c.position.x, c.position.y, c.position.z}},
          {"camera_look_at", {c.lookAt.x, c.lookAt.y, c.lookAt.z}},
          {"lights", scene.lights.size()},
          {"objects", objects}};
}

std::filesystem::path defaultOutput(const std::filesystem::path& scene) {
  return std::filesystem::path("out") / (scene.stem().string() + ".exr");
}

}  // namespace

namespace {

std::atomic<bool> gInterrupted{false};
sem_t* gWake = nullptr;
// How long a command has to stop by itself after SIGINT/SIGTERM before the watchdog ends it.
constexpr int kInterruptGraceMs = 100;

extern "C" void onInterrupt(int) {
  gInterrupted.store(true);
  if (gWake) sem_post(gWake);
}

}  // namespace

const std::atomic<bool>& interruptRequested() { return gInterrupted; }

namespace {

std::filesystem::path frameOutput(const std::filesystem::path& output, int frame, bool animated) {
  if (!animated) return output;
  char suffix[32];
  std::snprintf(suffix, sizeof suffix, "_%04d.exr", frame);
  return output.parent_path() / (output.stem().string() + suffix);
}

std::filesystem::path pngBeside(std::filesystem::path exr) { return exr.replace_extension(".png"); }

std::vector<int> framesToRender(const RenderCommandOptions& o, const Scene& scene) {
  const bool animated = !scene.path.keys.empty();
  if (!animated && (!o.frames.empty() || !o.shard.empty()))
    throw Error(scene.file.string() +
                ": path: --frames and --shard need a [path] with keyframes in the scene");
  const auto [first, last] = parseFrameRange(o.frames, animated ? scene.path.frames : 1);
  const auto [shard, shards] = parseShard(o.shard);
  std::vector<int> frames;
  for (int f = first; f <= last; ++f)
    if (f % shards == shard) frames.push_back(f);
  return frames;
}

std::string ffmpegOrThrow(const std::filesystem::path& video) {
  const std::string ffmpeg = findOnPath("ffmpeg");
  if (ffmpeg.empty())
    throw Error(video.string() +
                ": --video: expected ffmpeg on the PATH (Debian: apt-get install ffmpeg)");
  return ffmpeg;
}

// ffmpeg's image2 demuxer expands %d patterns: a literal % in the name is written %%.
std::string escapePercent(const std::string& s) {
  std::string out;
  for (char c : s) {
    out += c;
    if (c == '%') out += '%';
  }
  return out;
}

void assembleVideo(const std::string& ffmpeg, const std::filesystem::path& video,
                   const std::filesystem::path& output, double fps, int firstFrame) {
  const std::filesystem::path tmp = temporarySibling(video);
  const std::string pattern =
      (output.parent_path() / (escapePercent(output.stem().string()) + "_%04d.png")).string();
  const int status =
      runProgram({ffmpeg, "-nostdin", "-loglevel", "error", "-y", "-framerate", std::to_string(fps),
                  "-start_number", std::to_string(firstFrame), "-i", pattern, "-c:v", "libx264",
                  "-pix_fmt", "yuv420p", tmp.string()});
  std::error_code ec;
  if (status != 0) {
    std::filesystem::remove(tmp, ec);
    throw Error(video.string() + ": ffmpeg failed to assemble " + pattern +
                (status < 0 ? " (it did not start or was killed)"
                            : " (exit status " + std::to_string(status) + ")"));
  }
  std::filesystem::rename(tmp, video, ec);
  forgetTemporary(tmp);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw Error(video.string() + ": --video: cannot rename the complete video into place");
  }
}

}  // namespace

void installInterruptHandler() {
  // Commands poll interruptRequested() in their long loops and stop cleanly; a loop that does not
  // (inside a library, OpenSubdiv, table building) is stopped by this watchdog, woken by the
  // handler through a semaphore (sem_post is async-signal-safe): after a grace period it removes
  // every temporary and exits with 130. Final names only ever hold complete files, so nothing
  // partial remains either way.
  static sem_t wake;
  sem_init(&wake, 0, 0);
  gWake = &wake;
  std::thread([] {
    while (sem_wait(gWake) != 0) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(kInterruptGraceMs));
    removeTemporaries();
    static const char message[] =
        "meso: interrupted; complete outputs are kept, nothing partial was written\n";
    (void)!::write(2, message, sizeof message - 1);
    ::_exit(130);
  }).detach();
  std::signal(SIGINT, onInterrupt);
  std::signal(SIGTERM, onInterrupt);
}

void runRender(const RenderCommandOptions& o) {
  Timer total, phase;
  Scene scene = loadScene(o.scene);
  applyOverrides(o, scene);
  std::vector<std::string> memoryWarnings;
  checkRenderMemory(scene, memoryWarnings);
  for (const std::string& w : memoryWarnings)
    std::fprintf(stderr, "meso: warning: %s\n", w.c_str());
  const std::filesystem::path output = o.output.empty() ? defaultOutput(o.scene) : o.output;
  if (output.extension() != ".exr")
    throw Error(output.string() +
                ": output must be an .exr file (the PNG preview is written beside it)");
  // Every output is checked before any work: nothing is rendered for a run that cannot finish.
  checkOutputFile(output, "-o");
  checkOutputFile(pngBeside(output), "-o (its PNG preview)");
  if (!o.statsFile.empty()) checkOutputFile(o.statsFile, "--stats");
  std::string ffmpeg;
  if (!o.video.empty()) {
    checkOutputFile(o.video, "--video");
    ffmpeg = ffmpegOrThrow(o.video);
  }
  const bool animated = !scene.path.keys.empty();
  const std::vector<int> frames = framesToRender(o, scene);
  const std::optional<CameraPath> path =
      animated ? std::optional<CameraPath>(scene.path.keys) : std::nullopt;
  const double parseSeconds = phase.seconds();

  const int threads =
      scene.render.threads > 0 ? scene.render.threads : tbb::info::default_concurrency();
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  createOutputFolder(output.parent_path(), "-o");
  if (!o.statsFile.empty()) createOutputFolder(o.statsFile.parent_path(), "--stats");

  PrepareTimes prep;
  RenderContext ctx = prepareRenderContext(scene, prep, false);
  FrameGeometryStats geometry;
  if (!animated) geometry = prepareFrame(ctx, scene.camera, prep);
  size_t reportedWarnings = 0;
  const auto reportWarnings = [&] {
    for (; reportedWarnings < ctx.warnings.size(); ++reportedWarnings)
      std::fprintf(stderr, "meso: warning: %s\n", ctx.warnings[reportedWarnings].c_str());
  };
  reportWarnings();
  size_t maxMicropolygons = geometry.micropolygons, maxTriangles = ctx.numTriangles();
  double geometryMibPerMillion = 0.0;  // of the frame with the most micropolygons
  const auto noteGeometry = [&] {
    if (geometry.micropolygons == 0 || geometry.micropolygons < maxMicropolygons) return;
    geometryMibPerMillion = static_cast<double>(geometry.embreePeakBytes + geometry.meshBytes) /
                            (1024.0 * 1024.0) /
                            (static_cast<double>(geometry.micropolygons) * 1e-6);
  };
  noteGeometry();
  RenderCounters counters;
  nlohmann::json perFrame = nlohmann::json::array();
  double renderSeconds = 0.0, writeSeconds = 0.0;
  int rendered = 0, skipped = 0;
  // The last frame rendered stays staged until the stats are written: a run that cannot write its
  // stats leaves that frame under no final name.
  StagedFiles lastFrame;
  for (int f : frames) {
    const std::filesystem::path exr = frameOutput(output, f, animated), png = pngBeside(exr);
    if (animated) {
      checkOutputFile(exr, "-o");
      checkOutputFile(png, "-o (its PNG preview)");
    }
    if (animated && !o.overwrite && std::filesystem::exists(exr) && std::filesystem::exists(png)) {
      ++skipped;
      continue;
    }
    if (path) {
      geometry = prepareFrame(ctx, path->frame(f, scene.path.frames, scene.camera), prep);
      reportWarnings();
      maxMicropolygons = std::max(maxMicropolygons, geometry.micropolygons);
      noteGeometry();
      maxTriangles = std::max(maxTriangles, ctx.numTriangles());
    }
    phase.reset();
    const int64_t raysBefore = counters.rays.load();
    RenderOptions ro{scene.camera.spp, scene.render.seed, !o.quiet,
                     o.falseColour,    &gInterrupted,     !o.noBumpFilter};
    Image film;
    try {
      film = renderFrame(ctx, ro, counters);
    } catch (const Interrupted&) {
      lastFrame.commit();  // complete frames are kept
      throw RenderInterrupted();
    }
    const double r = phase.seconds();
    phase.reset();
    lastFrame.commit();
    lastFrame.stage(exr, encodeExr(film));
    lastFrame.stage(png, encodePngPreview(film));
    if (o.statsFile.empty()) lastFrame.commit();
    const double w = phase.seconds();
    renderSeconds += r;
    writeSeconds += w;
    ++rendered;
    perFrame.push_back({{"frame", f},
                        {"output", exr.string()},
                        {"rays", counters.rays.load() - raysBefore},
                        {"triangles", ctx.numTriangles()},
                        {"micropolygons", geometry.micropolygons},
                        {"micropolygons_off_screen", geometry.offScreenMicropolygons},
                        {"faces_diced", geometry.facesDiced},
                        {"dicing_coarsened_by", geometry.coarsening},
                        {"geometry_rebuilt", geometry.rebuilt},
                        {"seconds",
                         {{"tessellate", geometry.tessellateSeconds},
                          {"bvh", geometry.bvhSeconds},
                          {"render", r},
                          {"write", w}}}});
    if (!o.quiet)
      std::fprintf(stderr, "meso: wrote %s and %s (%dx%d, %d spp, %.2f s)\n", exr.string().c_str(),
                   png.string().c_str(), film.width, film.height, scene.camera.spp, r + w);
    if (gInterrupted.load()) {
      lastFrame.commit();
      throw RenderInterrupted();
    }
  }
  if (counters.nonFinite.load() > 0)
    std::fprintf(stderr,
                 "meso: warning: %lld NaN or infinite film values were written as 0 (a bug in "
                 "meso: please report "
                 "the scene)\n",
                 static_cast<long long>(counters.nonFinite.load()));
  if (!o.quiet && skipped > 0)
    std::fprintf(
        stderr,
        "meso: skipped %d frame(s) already complete on disk (use --overwrite to redo them)\n",
        skipped);
  const auto assemble = [&] {
    if (!o.video.empty())
      assembleVideo(ffmpeg, o.video, output, scene.path.fps, frames.empty() ? 0 : frames.front());
  };
  if (o.statsFile.empty()) assemble();

  if (!o.statsFile.empty()) {
    const double peak = peakRssMib();
    nlohmann::json stats = {
        {"seconds",
         {{"parse", parseSeconds + prep.load},
          {"tessellate", prep.tessellate},
          {"bvh", prep.bvh},
          {"render", renderSeconds},
          {"write", writeSeconds},
          {"total", total.seconds()}}},
        {"peak_rss_mib", peak},
        {"rays", counters.rays.load()},
        {"non_finite_values", counters.nonFinite.load()},
        {"triangles", maxTriangles},
        {"micropolygons", maxMicropolygons},
        {"tessellate_seconds", prep.tessellate},
        {"bvh_seconds", prep.bvh},
        {"peak_mib_per_million_micropolygons",
         maxMicropolygons > 0
             ? nlohmann::json(peak / (static_cast<double>(maxMicropolygons) * 1e-6))
             : nlohmann::json(nullptr)},
        {"geometry_mib_per_million_micropolygons",
         maxMicropolygons > 0 ? nlohmann::json(geometryMibPerMillion) : nlohmann::json(nullptr)},
        {"warnings", ctx.warnings},
        {"tables_built", prep.tablesBuilt},
        {"tables_from_cache", prep.tablesFromCache},
        {"tables_seconds", prep.tables},
        {"frames_rendered", rendered},
        {"frames_skipped", skipped},
        {"frames", perFrame},
        {"settings", settingsJson(scene, output)}};
    stats["settings"]["threads_used"] = threads;
    StagedFiles statsFile;
    statsFile.stage(o.statsFile, stats.dump(2) + "\n");
    lastFrame.commit();
    statsFile.commit();
    assemble();
  }
}

}  // namespace meso::app
