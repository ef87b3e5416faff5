// `meso trade`: options to the study of include/meso/trade/trade_study.h, its outputs to files.
// What is measured is documented in README.md (`meso trade`) and the library's headers.
#include "trade_command.h"

#include "cli_options.h"
#include "cli_values.h"
#include "command.h"
#include "external_program.h"
#include "interrupt.h"
#include "scene_options.h"

#include "meso/core/atomic_file.h"
#include "meso/core/error.h"
#include "meso/core/image_io.h"
#include "meso/render/integrator.h"
#include "meso/scene/camera_path.h"
#include "meso/scene/scene_parser.h"
#include "meso/trade/temporal_stability.h"
#include "meso/trade/trade_report.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <cmath>
#include <cstdio>

#ifndef MESO_PLOT_TRADE_SCRIPT
#define MESO_PLOT_TRADE_SCRIPT "tools/plot_trade.py"
#endif

namespace meso::app {
namespace {

namespace fs = std::filesystem;

// The swept values, frame size and --temporal.
void addSweepOptions(CLI::App* t, TradeCommandOptions& o) {
  addOption(t, "--d-values", o.settings.grid.dValues, "Transition D of the hybrid configurations")
      ->delimiter(',')
      ->capture_default_str();
  addOption(t, "--spp-values", o.settings.grid.sppValues,
            "Samples per pixel of every swept configuration")
      ->delimiter(',')
      ->capture_default_str();
  addOption(t, "--dicing-rates", o.settings.grid.dicingRates,
            "Dicing rates (pixels) of the displacement-only configurations")
      ->delimiter(',')
      ->capture_default_str();
  addOption(t, "--relief-samples-values", o.settings.grid.reliefSamples,
            "render.relief_samples of the displacement-only configurations (0: pixel dicing "
            "only)")
      ->delimiter(',')
      ->capture_default_str();
  addOption(t, "--hybrid-dicing-rates", o.settings.grid.hybridDicingRates,
            "Dicing rates (pixels) of the hybrid configurations (at the scene's D, for every spp)")
      ->delimiter(',')
      ->capture_default_str();
  addOption(t, "--width", o.width, "Image width in pixels (overrides camera.resolution)");
  addOption(t, "--height", o.height, "Image height in pixels (overrides camera.resolution)");
  addOption(t, "--threads", o.threads, "Worker threads, 0 = all cores (overrides render.threads)");
  t->add_flag(
      "--temporal", o.settings.temporal,
      "Also the frame-to-frame change of the default hybrid and the reference in "
      "bands around e1..e4 (needs a [path] and two or more frames); writes DIR/temporal.csv");
  t->add_flag("--temporal-only", o.temporalOnly,
              "Only the reference and the default hybrid, for --temporal");
  addOption(t, "--band", o.band, "Half width in T of the --temporal bands")->capture_default_str();
  t->add_flag("-q,--quiet", o.settings.quiet, "No progress on stderr");
}

CLI::App* addTradeOptions(CLI::App& cli, TradeCommandOptions& o) {
  CLI::App* t = cli.add_subcommand("trade",
                                   "Speed/accuracy trade: time, peak memory, micropolygons and "
                                   "error against a displacement reference refined "
                                   "until it converges (or a warning) for the hybrid over D x spp "
                                   "and dicing rate x spp and displacement alone "
                                   "over dicing rate x spp; writes DIR/trade.csv, DIR/trade.png "
                                   "(rmse against log time, Pareto front) and "
                                   "prints the default hybrid's ratios at equal rmse");
  addOption(t, "scene", o.scene, "Scene file")->required();
  addSetOption(t, o.set);
  addOption(t, "-o,--out-dir", o.outDir, "Folder for trade.csv, trade.png and temporal.csv")
      ->capture_default_str();
  addOption(t, "--frames", o.frames,
            "Frames A:B (inclusive) of the scene's [path]: times summed, errors averaged; "
            "default all");
  addOption(t, "--reference-spp", o.settings.reference.spp,
            "Samples per pixel of the reference's first level; each "
            "refinement doubles it")
      ->capture_default_str();
  addOption(t, "--reference-dicing-rate", o.settings.reference.dicingRate,
            "Dicing rate (pixels) of the reference's first level; each refinement halves it")
      ->capture_default_str();
  addOption(t, "--reference-tolerance", o.settings.reference.tolerance,
            "Percent: the reference has converged when a refinement changes its mean intensity "
            "by less (and "
            "the rmse is within --reference-rmse-tolerance)")
      ->capture_default_str();
  addOption(t, "--reference-rmse-tolerance", o.settings.reference.rmseTolerance,
            "Percent of the mean intensity: largest rmse between successive reference levels "
            "that counts as "
            "converged (it includes both levels' sampling noise)")
      ->capture_default_str();
  addOption(
      t, "--reference-max-refinements", o.settings.reference.maxRefinements,
      "Most refinements of the reference (dicing rate halved, spp doubled) after its first level")
      ->capture_default_str();
  addOption(t, "--reference-max-micropolygons", o.settings.reference.maxMicropolygons,
            "No reference level is started that would need more micropolygons (it would be "
            "about 4x the last)")
      ->capture_default_str();
  addOption(t, "--reference-cache", o.referenceCache,
            "Folder of cached reference renders (default: references/ in the table cache folder)");
  t->add_flag("--no-reference-cache", o.noReferenceCache,
              "Render the reference levels even if cached; store none");
  addSweepOptions(t, o);
  return t;
}

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

// trade.png from trade.csv with tools/plot_trade.py (matplotlib); the CSV stays the source, so a
// missing plotter costs the picture only, with a note on how to draw it.
void plot(const fs::path& csv, const fs::path& png, bool quiet) {
  const std::string script = MESO_PLOT_TRADE_SCRIPT;
  if (runPythonScript(script, {csv.string(), png.string()})) {
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

Scene loadTradeScene(const TradeCommandOptions& o, uint64_t memoryLimitBytes) {
  Scene scene = loadScene(o.scene, setOverrides(o.set), memoryLimitBytes);
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

void runTrade(const TradeCommandOptions& options, const RunContext& context) {
  TradeCommandOptions o = options;
  o.settings.memoryLimitBytes = context.memoryLimitBytes;
  o.settings.temporal = o.settings.temporal || o.temporalOnly;
  o.settings.grid.temporalOnly = o.temporalOnly;
  validate(o);
  const Scene scene = loadTradeScene(o, context.memoryLimitBytes);
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
  setImageThreads(threads);
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

}  // namespace

std::unique_ptr<Command> makeTradeCommand(CLI::App& cli) {
  return std::make_unique<OptionsCommand<TradeCommandOptions>>(cli, addTradeOptions, runTrade);
}

}  // namespace meso::app
