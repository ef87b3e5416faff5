#include "render_command.h"

#include "cli_values.h"
#include "frame_settings.h"
#include "interrupt.h"
#include "memory_estimates.h"
#include "render_report.h"
#include "render_stats.h"
#include "scene_options.h"
#include "video.h"
#include "view_check.h"

#include "meso/core/atomic_file.h"
#include "meso/core/error.h"
#include "meso/core/image_io.h"
#include "meso/core/input_file.h"
#include "meso/core/timer.h"
#include "meso/render/integrator.h"
#include "meso/render/render_context.h"
#include "meso/render/transition.h"
#include "meso/scene/camera_path.h"
#include "meso/scene/scene_parser.h"

#include <fmt/format.h>

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <optional>

namespace meso::app {
namespace {

std::filesystem::path defaultOutput(const std::filesystem::path& scene) {
  return std::filesystem::path("out") / (scene.stem().string() + ".exr");
}

std::filesystem::path frameOutput(const std::filesystem::path& output, int frame, bool animated) {
  if (!animated) return output;
  return output.parent_path() / fmt::format("{}_{:04}.exr", output.stem().string(), frame);
}

// .exr in any case (.EXR from a camera's or a tool's naming).
bool hasExrExtension(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e == ".exr";
}

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

// One `meso render` run: the checked plan, then the frames, then the stats and the video.
class RenderRun {
 public:
  RenderRun(const RenderCommandOptions& o, const RunContext& context) : o_(o), context_(context) {}

  void run() {
    plan();
    const int threads =
        scene_.render.threads > 0 ? scene_.render.threads : tbb::info::default_concurrency();
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    setImageThreads(threads);
    stats_.threads = threads;
    createOutputFolder(output_.parent_path(), "-o");
    if (!o_.statsFile.empty()) createOutputFolder(o_.statsFile.parent_path(), "--stats");
    if (animated_) storeFrameSettings(output_, settings_);
    ctx_.emplace(
        prepareRenderContext(scene_, prep_,
                             {.buildFrame = false,
                              .progress = !o_.quiet,
                              .memoryLimitBytes = context_.memoryLimitBytes,
                              .reservedBytes = reservedBytes_,
                              .filmBytes = filmBytes(scene_.camera.width, scene_.camera.height)}));
    // The cap the frames are diced under, for --stats.
    if (ctx_->maxMicropolygons < static_cast<size_t>(scene_.render.maxMicropolygons))
      scene_.render.maxMicropolygons = static_cast<int64_t>(ctx_->maxMicropolygons);
    warnObjectsOutOfView();
    if (!animated_) noteFrameGeometry(prepareFrame(*ctx_, scene_.camera, prep_));
    reportWarnings();
    stats_.maxTriangles = ctx_->numTriangles();
    for (int f : frames_) renderFrameOf(f);
    finish();
  }

 private:
  // Loads the scene and checks every output before any work: nothing is rendered for a run that
  // cannot finish.
  void plan() {
    scene_ = loadScene(o_.scene, sceneOverrides(o_), context_.memoryLimitBytes);
    applyRenderOptions(o_, scene_);
    window_ = cropWindow(o_, scene_.camera);
    if (scene_.lights.empty() && !scene_.environment)
      std::fprintf(stderr,
                   "meso: warning: %s has no lights: the image is black except for the "
                   "materials' ambient term ka\n",
                   o_.scene.string().c_str());
    reservedBytes_ = checkRenderMemory(scene_, context_.memoryLimitBytes);
    output_ = o_.output.empty() ? defaultOutput(o_.scene) : o_.output;
    if (!hasExrExtension(output_))
      throw Error(output_.string() +
                  ": output must be an .exr file (the PNG preview is written beside it)");
    checkOutputFile(output_, "-o");
    checkOutputFile(pngBeside(output_), "-o (its PNG preview)");
    if (!o_.statsFile.empty()) checkOutputFile(o_.statsFile, "--stats");
    if (!o_.video.empty()) {
      if (scene_.path.keys.empty())
        throw Error(o_.video.string() +
                    ": --video: expected a scene with a [path] (a fly-through); this one is a "
                    "still");
      checkOutputFile(o_.video, "--video");
      ffmpeg_ = ffmpegOrThrow(o_.video);
    }
    animated_ = !scene_.path.keys.empty();
    frames_ = framesToRender(o_, scene_);
    for (int f : frames_) toRender_ += !completeOnDisk(frameOutput(output_, f, animated_));
    if (animated_) {
      settings_ =
          frameSettings(scene_, readInputFile(o_.scene, "scene", kMaxSceneBytes), o_, window_);
      checkOutputFile(settingsFileFor(output_), "-o (the frames' settings file)");
      if (!o_.overwrite) checkResumedSettings(output_, settings_);
      path_.emplace(scene_.path.keys);
    }
    stats_.parseSeconds = total_.seconds();
  }

  // Objects none of this run's frames shows (also with -q, like the other warnings).
  void warnObjectsOutOfView() const {
    std::vector<CameraSettings> cameras;
    for (int f : frames_)
      cameras.push_back(animated_ ? path_->frame(f, scene_.path.frames, scene_.camera)
                                  : scene_.camera);
    for (const std::string& w : objectsOutOfView(scene_, *ctx_, cameras))
      std::fprintf(stderr, "meso: warning: %s\n", w.c_str());
  }

  // A frame of a path whose EXR and PNG exist: skipped unless --overwrite.
  bool completeOnDisk(const std::filesystem::path& exr) const {
    return animated_ && !o_.overwrite && std::filesystem::exists(exr) &&
           std::filesystem::exists(pngBeside(exr));
  }

  void reportWarnings() {
    const std::vector<std::string> warnings = ctx_->warnings.list();
    for (; reportedWarnings_ < warnings.size(); ++reportedWarnings_)
      std::fprintf(stderr, "meso: warning: %s\n", warnings[reportedWarnings_].c_str());
  }

  void noteFrameGeometry(const FrameGeometryStats& geometry) {
    geometry_ = geometry;
    reportWarnings();
    stats_.maxTriangles = std::max(stats_.maxTriangles, ctx_->numTriangles());
    if (geometry.micropolygons == 0 || geometry.micropolygons < stats_.maxMicropolygons) return;
    stats_.maxMicropolygons = geometry.micropolygons;
    const double millions = static_cast<double>(geometry.micropolygons) * 1e-6;
    stats_.geometryMibPerMillion =
        static_cast<double>(geometry.embreePeakBytes + geometry.meshBytes) / (1024.0 * 1024.0) /
        millions;
    stats_.meshMibPerMillion =
        static_cast<double>(geometry.meshBytes) / (1024.0 * 1024.0) / millions;
  }

  // "frame i of N" of a path with the run's ETA, before the frame's own progress bar.
  void announceFrame(int f) const {
    if (o_.quiet) return;
    const int index = stats_.rendered + 1;
    std::fprintf(stderr, "meso: %s\n",
                 frameLine(index, std::max(toRender_, index), f, scene_.path.frames,
                           total_.seconds(), framesSeconds_)
                     .c_str());
  }

  // Renders frame f and stages its EXR and PNG (committed at once without --stats, else with the
  // stats: a run that cannot write its stats leaves its last frame under no final name).
  void renderFrameOf(int f) {
    const std::filesystem::path exr = frameOutput(output_, f, animated_), png = pngBeside(exr);
    if (animated_) {
      checkOutputFile(exr, "-o");
      checkOutputFile(png, "-o (its PNG preview)");
      if (completeOnDisk(exr)) {
        ++stats_.skipped;
        return;
      }
      announceFrame(f);
    }
    Timer frameClock;
    if (animated_) {
      noteFrameGeometry(
          prepareFrame(*ctx_, path_->frame(f, scene_.path.frames, scene_.camera), prep_));
    }
    Timer phase;
    const int64_t raysBefore = counters_.rays.load();
    const RenderOptions ro{.spp = scene_.camera.spp,
                           .seed = scene_.render.seed,
                           .progress = !o_.quiet,
                           .falseColour = o_.falseColour,
                           .cancel = &interruptRequested(),
                           .filterBump = !o_.noBumpFilter,
                           .filterTextures = !o_.noTextureFilter,
                           .window = window_};
    Image film;
    try {
      film = renderFrame(*ctx_, ro, counters_);
    } catch (const Interrupted&) {
      lastFrame_.commit();  // complete frames are kept
      throw RenderInterrupted();
    }
    const double r = phase.seconds();
    phase.reset();
    lastFrame_.commit();
    const size_t triangles = ctx_->numTriangles();
    // Geometry no later frame reuses (after the last frame, or made for this view) is freed before
    // the images are encoded, whose buffers would otherwise come on top of it.
    if (f == frames_.back() || ctx_->viewDependent()) releaseFrameGeometry(*ctx_);
    // The two encodings side by side: the PNG on a worker, the EXR here (its blocks compressed on
    // OpenEXR's threads), so that its large buffers come from this thread's heap, where the
    // frame's freed memory is, not from a worker's arena.
    std::string exrBytes, pngBytes;
    tbb::task_group preview;
    preview.run([&] { pngBytes = encodePngPreview(film); });
    try {
      exrBytes = encodeExr(film);
    } catch (...) {
      preview.wait();
      throw;
    }
    preview.wait();
    lastFrame_.stage(exr, exrBytes);
    lastFrame_.stage(png, pngBytes);
    if (o_.statsFile.empty()) lastFrame_.commit();
    const double w = phase.seconds();
    stats_.renderSeconds += r, stats_.writeSeconds += w, ++stats_.rendered;
    framesSeconds_ += frameClock.seconds();
    written_.exrs.push_back(exr);
    stats_.perFrame.push_back(
        frameJson(f, exr, counters_.rays.load() - raysBefore, triangles, geometry_, r, w));
    if (!o_.quiet)
      std::fprintf(stderr, "meso: wrote %s and %s (%dx%d, %d spp, %.2f s)\n", exr.string().c_str(),
                   png.string().c_str(), film.width, film.height, scene_.camera.spp, r + w);
    if (interruptRequested().load()) {
      lastFrame_.commit();
      throw RenderInterrupted();
    }
  }

  void finish() {
    if (counters_.nonFinite.load() > 0)
      std::fprintf(stderr,
                   "meso: warning: %lld NaN or infinite film values were written as 0 (a bug in "
                   "meso: please report the scene)\n",
                   static_cast<long long>(counters_.nonFinite.load()));
    if (!o_.quiet && stats_.skipped > 0)
      std::fprintf(
          stderr,
          "meso: skipped %d frame(s) already complete on disk (use --overwrite to redo them)\n",
          stats_.skipped);
    if (!o_.statsFile.empty()) {
      stats_.totalSeconds = total_.seconds();
      const nlohmann::json stats =
          statsJson(scene_, output_, stats_, prep_, counters_, ctx_->warnings.list());
      StagedFiles statsFile;
      statsFile.stage(o_.statsFile, stats.dump(2) + "\n");
      lastFrame_.commit();
      statsFile.commit();
    }
    if (!o_.video.empty())
      assembleVideo(ffmpeg_, o_.video, output_, scene_.path.fps,
                    frames_.empty() ? 0 : frames_.front());
    written_.animated = animated_;
    written_.stats = o_.statsFile;
    written_.video = o_.video;
    if (!o_.quiet) std::fprintf(stderr, "meso: %s\n", writtenLine(written_).c_str());
  }

  const RenderCommandOptions& o_;
  const RunContext context_;
  Timer total_;
  Scene scene_;
  double reservedBytes_ = 0.0;  // the film and tables, as checkRenderMemory estimated them
  std::filesystem::path output_;
  std::string ffmpeg_;
  bool animated_ = false;
  std::vector<int> frames_;
  int toRender_ = 0;            // frames_ not complete on disk at the start
  double framesSeconds_ = 0.0;  // spent on the frames rendered so far
  WrittenFiles written_;
  nlohmann::json settings_;  // of a path's frames (frame_settings.h)
  std::optional<CameraPath> path_;
  std::optional<PixelWindow> window_;  // --crop
  PrepareTimes prep_;
  std::optional<RenderContext> ctx_;  // after plan()
  FrameGeometryStats geometry_;
  size_t reportedWarnings_ = 0;
  RenderCounters counters_;
  RenderRunStats stats_;
  StagedFiles lastFrame_;  // the last frame rendered, staged until the stats are written
};

void runRender(const RenderCommandOptions& options, const RunContext& context) {
  RenderRun(options, context).run();
}

}  // namespace

std::unique_ptr<Command> makeRenderCommand(CLI::App& cli) {
  return std::make_unique<OptionsCommand<RenderCommandOptions>>(cli, addRenderOptions, runRender);
}

}  // namespace meso::app
