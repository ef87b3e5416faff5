// `meso trade`: options to the study of include/meso/trade/trade_study.h, its outputs to files.
// What is measured is documented in README.md (`meso trade`) and the library's headers.
#include "trade_command.h"
#include "scene_options.h"

#include "cli_values.h"
#include "external_program.h"
#include "render_command.h"

#include "meso/core/atomic_file.h"
#include "meso/core/error.h"
#include "meso/render/integrator.h"
#include "meso/scene/camera_path.h"
#include "meso/scene/scene_parser.h"
#include "meso/trade/temporal_stability.h"
#include "meso/trade/trade_report.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <cmath>
#include <cstdio>

#include <unistd.h>

#ifndef MESO_PLOT_TRADE_SCRIPT
#define MESO_PLOT_TRADE_SCRIPT "tools/plot_trade.py"
#endif

namespace meso::app {
namespace {

namespace fs = std::filesystem;

void checkRange(double v, const char* option, double lo, double hi) {
  if (!std::isfinite(v) || v < lo || v > hi)
    throw Error(std::string(option) + ": " + trade::formatNumber(v) + " is outside [" +
                trade::formatNumber(lo) + ", " + trade::formatNumber(hi) + "]");
}

void validate(const TradeCommandOptions& o) {
  trade::validateTradeSettings(o.settings);
  if (o.width) checkRange(*o.width, "--width", 1, 16384);
  if (o.height) checkRange(*o.height, "--height", 1, 16384);
  if (o.threads) checkRange(*o.threads, "--threads", 0, 1024);
  checkRange(o.band, "--band", 0, 1e6);
}

std::vector<CameraSettings> cameras(const TradeCommandOptions& o, const Scene& scene) {
  if (scene.path.keys.empty()) {
    if (!o.frames.empty())
      throw Error(scene.file.string() +
                  ": path: --frames needs a [path] with keyframes in the scene");
    return {scene.camera};
  }
  const CameraPath path(scene.path.keys);
  const auto [first, last] = parseFrameRange(o.frames, scene.path.frames);
  std::vector<CameraSettings> result;
  for (int f = first; f <= last; ++f)
    result.push_back(path.frame(f, scene.path.frames, scene.camera));
  return result;
}

// Debian's python3 first: tools/install-deps installs matplotlib for it.
std::string python() {
  if (::access("/usr/bin/python3", X_OK) == 0) return "/usr/bin/python3";
  return findOnPath("python3");
}

// trade.png from trade.csv with tools/plot_trade.py (matplotlib); the CSV stays the source, so a
// missing plotter costs the picture only, with a note on how to draw it.
void plot(const fs::path& csv, const fs::path& png, bool quiet) {
  const std::string script = MESO_PLOT_TRADE_SCRIPT, py = python();
  const bool ran = !py.empty() && fs::exists(script) &&
                   runProgram({py, script, csv.string(), png.string()}) == 0;
  if (ran) {
    if (!quiet) std::fprintf(stderr, "meso: wrote %s\n", png.string().c_str());
    return;
  }
  std::error_code ignored;
  fs::remove(png, ignored);  // a plot of an earlier run would not match the new CSV
  std::fprintf(stderr,
               "meso: warning: %s not plotted (needs python3 with matplotlib: apt-get install "
               "python3-matplotlib); to plot it: python3 %s %s %s\n",
               png.string().c_str(), script.c_str(), csv.string().c_str(), png.string().c_str());
}

Scene loadTradeScene(const TradeCommandOptions& o) {
  Scene scene = loadScene(o.scene, setOverrides(o.set));
  if (o.width) scene.camera.width = *o.width;
  if (o.height) scene.camera.height = *o.height;
  if (o.threads) scene.render.threads = *o.threads;
  return scene;
}

void writeTemporal(const TradeCommandOptions& o, const trade::TradeStudy& study,
                   const Scene& scene) {
  const std::vector<trade::TemporalBand> bands = trade::temporalBands(
      study.defaultHybrid, study.reference.reference(), scene.render.transition, o.band);
  std::fputs(trade::temporalTable(bands, o.band).c_str(), stdout);
  writeFileAtomically(o.outDir / "temporal.csv", trade::temporalCsv(bands, o.band));
  if (!o.settings.quiet)
    std::fprintf(stderr, "meso: wrote %s\n", (o.outDir / "temporal.csv").string().c_str());
}

}  // namespace

void runTrade(const TradeCommandOptions& options) {
  TradeCommandOptions o = options;
  o.settings.temporal = o.settings.temporal || o.temporalOnly;
  o.settings.grid.temporalOnly = o.temporalOnly;
  validate(o);
  const Scene scene = loadTradeScene(o);
  const std::vector<CameraSettings> cams = cameras(o, scene);
  if (o.settings.temporal && cams.size() < 2)
    throw Error(
        "--temporal: needs at least two frames: a scene with a [path] and --frames A:B with B > A");
  const std::vector<trade::Configuration> configs = trade::configurations(o.settings.grid, scene);
  for (const trade::Configuration& c : configs)
    trade::sceneFor(scene, c);  // checks every D before rendering anything
  createOutputFolder(o.outDir, "-o");
  for (const char* name : {"trade.csv", "trade.png", "temporal.csv"})
    checkOutputFile(o.outDir / name, "-o");

  const int threads =
      scene.render.threads > 0 ? scene.render.threads : tbb::info::default_concurrency();
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  if (!o.settings.quiet)
    std::fprintf(stderr, "meso: trade: %zu configurations x %zu frame(s) at %dx%d, %d threads\n",
                 configs.size(), cams.size(), scene.camera.width, scene.camera.height, threads);
  const trade::ReferenceCache cache(o.noReferenceCache ? fs::path()
                                    : o.referenceCache.empty()
                                        ? trade::ReferenceCache::defaultFolder(scene)
                                        : o.referenceCache);
  trade::TradeStudy study;
  try {
    study = trade::runTradeStudy(scene, cams, o.settings, cache, &interruptRequested());
  } catch (const Interrupted&) {
    throw RenderInterrupted();
  }
  writeFileAtomically(o.outDir / "trade.csv", trade::tradeCsv(study.results, study.reference));
  if (!o.settings.quiet)
    std::fprintf(stderr, "meso: wrote %s\n", (o.outDir / "trade.csv").string().c_str());
  plot(o.outDir / "trade.csv", o.outDir / "trade.png", o.settings.quiet);
  std::printf("%s\n", trade::tradeSummary(study.results, study.reference).c_str());
  if (o.settings.temporal) writeTemporal(o, study, scene);
}

}  // namespace meso::app
