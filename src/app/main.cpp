// The meso command line: parses options and calls the library. Exit status 2 on bad input.
#include "bands_command.h"
#include "cli_choices.h"
#include "cache_command.h"
#include "cli_values.h"
#include "consistency_command.h"
#include "render_command.h"
#include "scene_options.h"
#include "tables_command.h"
#include "trade_command.h"

#include "meso/core/error.h"
#include "meso/core/memory_budget.h"
#include "meso/core/progress.h"
#include "meso/scene/choices.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

namespace {

using meso::app::addChoice;
using meso::app::addChoices;

void addRenderCommand(CLI::App& cli, meso::app::RenderCommandOptions& o) {
  CLI::App* render = meso::app::addRenderOptions(cli, o);
  render->callback([&o] {
    meso::setProgressAllowed(!o.quiet);
    meso::app::runRender(o);
  });
}

void addConsistencyCommand(CLI::App& cli, meso::app::ConsistencyCommandOptions& o) {
  CLI::App* c = cli.add_subcommand("consistency",
                                   "Becker & Max's Figure 6 for any relief: area-averaged "
                                   "intensity of a flat periodic patch for "
                                   "bump, redistribution, brdf and displacement at each theta_V; "
                                   "given a SCENE, the same for the "
                                   "whole scene: each renderer against a full-displacement "
                                   "reference, per object and band of rows");
  c->add_option("scene", o.scene,
                "Scene file (TOML): compare renderers on the whole scene instead of the patch")
      ->check(CLI::ExistingFile);
  meso::app::addSetOption(c, o.set);
  c->add_option("--bands", o.bands, "SCENE: bands of image rows")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  c->add_option("--reference-dicing", o.referenceDicing,
                "SCENE: dicing rate of the displacement reference, pixels")
      ->check(CLI::Range(0.01f, 100.0f))
      ->capture_default_str();
  c->add_option("--reference-spp", o.referenceSpp,
                "SCENE: samples per pixel of the reference (0: the scene's)")
      ->check(CLI::Range(0, 65536))
      ->capture_default_str();
  addChoices(c, "--algorithms", o.algorithms,
             "SCENE: renderers compared with the reference, comma separated");
  c->add_option("--height", o.height,
                "Height image (any format OpenImageIO reads); default: procedural fBm noise")
      ->check(CLI::ExistingFile);
  c->add_option("--amplitude", o.amplitude,
                "Relief amplitude in units of one tile (the tile is 1 x 1)")
      ->check(CLI::Range(0.0f, 10.0f))
      ->capture_default_str();
  c->add_option("--scale", o.scale, "Tiling scale S: the height table repeats S times per tile")
      ->check(CLI::Range(1e-3f, 1e3f))
      ->capture_default_str();
  c->add_option("--octaves", o.octaves, "Octaves of the procedural noise")
      ->check(CLI::Range(1, 12))
      ->capture_default_str();
  c->add_option("--seed", o.seed, "Seed of the procedural noise")->capture_default_str();
  c->add_option("--theta-v", o.thetaV, "View angles in degrees, comma separated")
      ->delimiter(',')
      ->capture_default_str();
  c->add_option("--theta-l", o.thetaL, "Light polar angle in degrees")
      ->check(CLI::Range(0.0f, 90.0f))
      ->capture_default_str();
  c->add_option("--phi", o.phi, "phi_V - phi_L in degrees")
      ->check(CLI::Range(-360.0f, 360.0f))
      ->capture_default_str();
  addChoice(c, "--component", o.component,
            "Terms of the local model: " + meso::choiceList<meso::Component>("|"));
  c->add_option("--phong", o.phong, "Phong exponent of the specular component")
      ->check(CLI::Range(0.0f, 10000.0f))
      ->capture_default_str();
  addChoice(c, "--format", o.format, meso::choiceList<meso::TableFormat>("|"));
  c->add_option("--normalize", o.normalize,
                "Scale so that bump at the first theta_V equals this (the paper used 128)");
  c->add_option("--samples", o.samples, "Samples per view azimuth")
      ->check(CLI::Range(16, 1 << 24))
      ->capture_default_str();
  c->add_option("--azimuths", o.azimuths, "View azimuths averaged")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  addChoice(c, "--variant", o.variant,
            "Redistribution maps: " + meso::choiceList<meso::RedistributionVariant>("|"));
  c->add_option(
      "--cache-dir", o.cacheDir,
      "Table cache folder (default $MESO_CACHE_DIR, $XDG_CACHE_HOME/meso or ~/.cache/meso)");
  c->add_flag("--no-cache", o.noCache, "Build the tables without reading or writing the cache");
  c->add_flag("--shadows", o.shadows,
              "Relief self-shadowing: shadow rays in displacement, the traced shadowing factor in "
              "redistribution and brdf "
              "(SCENE: the scene's render.shadows is used)");
  c->add_option("--shadow-rays", o.shadowRays,
                "--shadows: visible hits per view slice of the shadowing table (0: the renderer's)")
      ->check(CLI::Range(0, 1 << 22));
  c->callback([&o] { meso::app::runConsistency(o); });
}

void addTablesCommand(CLI::App& cli, meso::app::TablesCommandOptions& o) {
  CLI::App* t = cli.add_subcommand(
      "tables",
      "Build (or load from the cache) the appearance tables of the scene's relief levels; print "
      "build time, "
      "size and cache hit/miss per level as CSV; plot histograms and BRDF slices as PNG");
  t->add_option("scene", o.scene, "Scene file")->required();
  meso::app::addSetOption(t, o.set);
  t->add_option("-o,--out-dir", o.outDir, "Folder for the plots")->capture_default_str();
  t->add_flag("--no-plots", o.noPlots, "Only build and report");
  t->callback([&o] { meso::app::runTables(o); });
}

void addBandsCommand(CLI::App& cli, meso::app::BandsCommandOptions& o) {
  CLI::App* b = cli.add_subcommand(
      "bands",
      "Split one height map into band-limited relief levels whose sum reproduces it (Becker & Max "
      "1993, 4.3); "
      "writes one EXR per band and prints each band's measured highest frequency");
  b->add_option("height", o.height, "Height image (any format OpenImageIO reads)")
      ->required()
      ->check(CLI::ExistingFile);
  b->add_option("-n,--levels", o.levels, "Number of bands")
      ->check(CLI::Range(1, 16))
      ->capture_default_str();
  b->add_option("-o,--out-dir", o.outDir, "Folder for the band images")->capture_default_str();
  b->add_flag("--clamp", o.clamp, "The map does not tile (it is mirrored before filtering)");
  b->callback([&o] { meso::app::runBands(o); });
}

void addCacheCommand(CLI::App& cli, meso::app::CacheCommandOptions& o) {
  CLI::App* c = cli.add_subcommand(
      "cache", "The table cache folder: list its tables, clear it, or prune it to a size");
  c->require_subcommand(1);
  const auto addFolder = [&o](CLI::App* sub) {
    sub->add_option(
        "--cache-dir", o.cacheDir,
        "Table cache folder (default $MESO_CACHE_DIR, $XDG_CACHE_HOME/meso or ~/.cache/meso)");
  };
  CLI::App* list = c->add_subcommand(
      "list",
      "One line per table, least recently used first: file, size, last use; then the total");
  addFolder(list);
  list->callback([&o] { meso::app::runCacheList(o); });
  CLI::App* clear =
      c->add_subcommand("clear", "Remove every table and lock file (those in use are kept)");
  addFolder(clear);
  clear->callback([&o] { meso::app::runCacheClear(o); });
  CLI::App* prune = c->add_subcommand(
      "prune",
      "Remove least recently used tables until the rest fit in a size (the same eviction "
      "that runs after every store)");
  addFolder(prune);
  prune->add_option("--to,--cache-limit", o.to,
                    "Size to prune to: bytes with an optional K, M, G or T suffix (500M, 4G); "
                    "default $MESO_CACHE_LIMIT, else 4G");
  prune->callback([&o] { meso::app::runCachePrune(o); });
}

// Options live for the whole run (CLI11 writes into them when it parses).
void addTradeCommand(CLI::App& cli) {
  static meso::app::TradeCommandOptions o;
  CLI::App* t = cli.add_subcommand("trade",
                                   "Speed/accuracy trade: time, peak memory, micropolygons and "
                                   "error against a displacement reference refined "
                                   "until it converges (or a warning) for the hybrid over D x spp "
                                   "and dicing rate x spp and displacement alone "
                                   "over dicing rate x spp; writes DIR/trade.csv, DIR/trade.png "
                                   "(rmse against log time, Pareto front) and "
                                   "prints the default hybrid's ratios at equal rmse");
  t->add_option("scene", o.scene, "Scene file")->required();
  meso::app::addSetOption(t, o.set);
  t->add_option("-o,--out-dir", o.outDir, "Folder for trade.csv, trade.png and temporal.csv")
      ->capture_default_str();
  t->add_option("--frames", o.frames,
                "Frames A:B (inclusive) of the scene's [path]: times summed, errors averaged; "
                "default all");
  t->add_option("--reference-spp", o.settings.reference.spp,
                "Samples per pixel of the reference's first level; each "
                "refinement doubles it")
      ->capture_default_str();
  t->add_option("--reference-dicing-rate", o.settings.reference.dicingRate,
                "Dicing rate (pixels) of the reference's first level; each refinement halves it")
      ->capture_default_str();
  t->add_option("--reference-tolerance", o.settings.reference.tolerance,
                "Percent: the reference has converged when a refinement changes its mean intensity "
                "by less (and "
                "the rmse is within --reference-rmse-tolerance)")
      ->capture_default_str();
  t->add_option("--reference-rmse-tolerance", o.settings.reference.rmseTolerance,
                "Percent of the mean intensity: largest rmse between successive reference levels "
                "that counts as "
                "converged (it includes both levels' sampling noise)")
      ->capture_default_str();
  t->add_option(
       "--reference-max-refinements", o.settings.reference.maxRefinements,
       "Most refinements of the reference (dicing rate halved, spp doubled) after its first level")
      ->capture_default_str();
  t->add_option("--reference-max-micropolygons", o.settings.reference.maxMicropolygons,
                "No reference level is started that would need more micropolygons (it would be "
                "about 4x the last)")
      ->capture_default_str();
  t->add_option(
      "--reference-cache", o.referenceCache,
      "Folder of cached reference renders (default: references/ in the table cache folder)");
  t->add_flag("--no-reference-cache", o.noReferenceCache,
              "Render the reference levels even if cached; store none");
  t->add_option("--d-values", o.settings.grid.dValues, "Transition D of the hybrid configurations")
      ->delimiter(',')
      ->capture_default_str();
  t->add_option("--spp-values", o.settings.grid.sppValues,
                "Samples per pixel of every swept configuration")
      ->delimiter(',')
      ->capture_default_str();
  t->add_option("--dicing-rates", o.settings.grid.dicingRates,
                "Dicing rates (pixels) of the displacement-only configurations")
      ->delimiter(',')
      ->capture_default_str();
  t->add_option("--relief-samples-values", o.settings.grid.reliefSamples,
                "render.relief_samples of the displacement-only configurations (0: pixel dicing "
                "only)")
      ->delimiter(',')
      ->capture_default_str();
  t->add_option(
       "--hybrid-dicing-rates", o.settings.grid.hybridDicingRates,
       "Dicing rates (pixels) of the hybrid configurations (at the scene's D, for every spp)")
      ->delimiter(',')
      ->capture_default_str();
  t->add_option("--width", o.width, "Image width in pixels (overrides camera.resolution)");
  t->add_option("--height", o.height, "Image height in pixels (overrides camera.resolution)");
  t->add_option("--threads", o.threads, "Worker threads, 0 = all cores (overrides render.threads)");
  t->add_flag(
      "--temporal", o.settings.temporal,
      "Also the frame-to-frame change of the default hybrid and the reference in "
      "bands around e1..e4 (needs a [path] and two or more frames); writes DIR/temporal.csv");
  t->add_flag("--temporal-only", o.temporalOnly,
              "Only the reference and the default hybrid, for --temporal");
  t->add_option("--band", o.band, "Half width in T of the --temporal bands")->capture_default_str();
  t->add_flag("-q,--quiet", o.settings.quiet, "No progress on stderr");
  t->callback([] {
    meso::setProgressAllowed(!o.settings.quiet);
    meso::app::runTrade(o);
  });
}

// CLI11 reads "nan" and "inf" into floats, and Range() lets NaN through (every comparison with it
// is false): every floating-point option of every command must be a finite number. And it wraps
// "-1" into an unsigned option: every unsigned one must be a whole number of 0 or more.
// An empty text value is refused too.
void requireSaneValues(CLI::App& app) {
  const CLI::Validator finite(
      [](std::string& text) { return meso::app::finiteNumberProblem(text); }, "FINITE",
      "finite number");
  const CLI::Validator whole(
      [](std::string& text) { return meso::app::unsignedNumberProblem(text); }, "UNSIGNED",
      "whole number of 0 or more");
  // Paths and other text: an empty value (`-o ''`) is refused, not taken for the default.
  const CLI::Validator nonEmpty(
      [](std::string& text) {
        return text.empty() ? std::string("expected a value, got an empty string") : std::string();
      },
      "", "non-empty");
  for (CLI::Option* option : app.get_options()) {
    const std::string type = option->get_type_name();
    if (type.find("FLOAT") != std::string::npos) option->check(finite);
    if (type.find("UINT") != std::string::npos) option->check(whole);
    if (type.find("TEXT") != std::string::npos) option->check(nonEmpty);
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) requireSaneValues(*sub);
}

// --memory-limit on every command; applied while parsing, before the command runs.
void addMemoryLimit(CLI::App& app) {
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
    sub->add_option_function<uint64_t>(
           "--memory-limit", [](const uint64_t& mib) { meso::setMemoryLimitBytes(mib << 20); },
           "MiB a job may use: jobs estimated above it are refused before allocating (default "
           "half of physical memory, here " +
               std::to_string(meso::defaultMemoryLimitBytes() >> 20) + ")")
        ->check(CLI::Range(uint64_t{16}, uint64_t{1} << 30))
        ->default_str(std::to_string(meso::defaultMemoryLimitBytes() >> 20));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"meso: bumpy surfaces at every distance (Becker & Max 1993)"};
  cli.set_version_flag("--version", "meso " MESO_VERSION, "Print meso's version and exit");
  cli.require_subcommand(1);
  meso::app::RenderCommandOptions renderOptions;
  addRenderCommand(cli, renderOptions);
  meso::app::ConsistencyCommandOptions consistencyOptions;
  addConsistencyCommand(cli, consistencyOptions);
  meso::app::TablesCommandOptions tablesOptions;
  addTablesCommand(cli, tablesOptions);
  meso::app::BandsCommandOptions bandsOptions;
  addBandsCommand(cli, bandsOptions);
  addTradeCommand(cli);
  meso::app::CacheCommandOptions cacheOptions;
  addCacheCommand(cli, cacheOptions);
  requireSaneValues(cli);
  addMemoryLimit(cli);
  meso::app::installInterruptHandler();
  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int status = cli.exit(e);
    return status == 0 ? 0 : 2;
  } catch (const meso::app::RenderInterrupted&) {
    std::fprintf(stderr,
                 "meso: interrupted; complete frames are kept, nothing partial was written\n");
    return meso::app::interruptedStatus();
  } catch (const meso::Error& e) {
    std::fprintf(stderr, "meso: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "meso: internal error: %s\n", e.what());
    return 1;
  }
  return 0;
}
