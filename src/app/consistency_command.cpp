#include "consistency_command.h"

#include "cli_options.h"
#include "command.h"
#include "interrupt.h"
#include "scene_options.h"

#include "meso/appearance/table_cache.h"
#include "meso/core/error.h"
#include "meso/core/math.h"
#include "meso/render/consistency.h"
#include "meso/render/environment_map.h"
#include "meso/render/integrator.h"
#include "meso/appearance/material_tables.h"
#include "meso/render/local_contrast.h"
#include "meso/render/scene_consistency.h"
#include "meso/scene/scene_parser.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

namespace meso::app {
namespace {

ReliefLevelDecl reliefFrom(const ConsistencyCommandOptions& o) {
  ReliefLevelDecl d;
  d.loc.file = o.height.empty() ? "<command line>" : o.height.string();
  d.source = o.height.empty() ? ReliefSource::Noise : ReliefSource::Image;
  d.height = o.height;
  d.amplitude = o.amplitude;
  d.scale = o.scale;
  d.octaves = o.octaves;
  d.seed = o.seed;
  return d;
}

// "as detailed (...): fails: brdf, redistribution; worst ..." for stderr.
std::string detailVerdict(const SceneConsistencyReport& report, float referenceDicing) {
  const std::string head = fmt::format(
      "as detailed (local contrast within {:g}% of the reference's where its contrast is at least "
      "{:g}): ",
      100.0 * kContrastTolerance, kReliefContrastFloor);
  if (std::isnan(report.worstContrastRatio)) return head + "no region shows relief";
  std::string failing;
  for (const std::string& r : report.notDetailed) failing += (failing.empty() ? "" : ", ") + r;
  return head + (failing.empty() ? std::string("every renderer passes") : "fails: " + failing) +
         fmt::format(
             "; worst: {} in {}, contrast ratio {:.3f}; the reference's contrast moves {:.2f}% "
             "when diced at {:g} px",
             report.worstContrastRenderer, report.worstContrastRegion, report.worstContrastRatio,
             100.0 * report.referenceContrastChange, 2.0 * referenceDicing);
}

// A reference that moves less than this when its dicing is halved counts as converged.
constexpr double kConvergedChange = 0.01;

// The cap coarsened the reference farthest first: which regions lie wholly nearer than where it
// began (diced as asked) and whether the reference converged in each of them.
std::string coarsenedReferenceWarning(const SceneConsistencyReport& report, float dicing) {
  std::string asAsked, beyond;
  for (const ConsistencyRegion& r : report.regions) {
    if (r.pixels == 0 || !(r.mean[0] > 0.0)) continue;
    const double change = std::abs(r.mean[1] / r.mean[0] - 1.0);
    if (r.farthest < report.referenceAsAskedWithin)
      asAsked +=
          fmt::format("{}{} ({}: moves {:.2f}%)", asAsked.empty() ? "" : ", ", r.name,
                      change <= kConvergedChange ? "converged" : "not converged", 100.0 * change);
    else
      beyond +=
          fmt::format("{}{} (to {:.3g} units)", beyond.empty() ? "" : ", ", r.name, r.farthest);
  }
  return fmt::format(
      "WARNING: the micropolygon cap (render.max_micropolygons) coarsened the reference beyond "
      "{:.3g} units from the eye (farthest geometry first). Diced as asked: {}. Reaching beyond "
      "it, where the reference's change when diced at {:g} px says nothing about its "
      "convergence: {}. Raise render.max_micropolygons in the scene or --reference-dicing",
      report.referenceAsAskedWithin, asAsked.empty() ? "no region" : asAsked, 2.0 * dicing,
      beyond.empty() ? "no region" : beyond);
}

// The patch's relief, light and tables (the options that apply without a SCENE too).
void addPatchOptions(CLI::App* c, ConsistencyCommandOptions& o) {
  addOption(c, "--height", o.height,
            "Height image (any format OpenImageIO reads); default: procedural fBm noise",
            CLI::ExistingFile);
  addOption(c, "--amplitude", o.amplitude,
            "Relief amplitude in units of one tile (the tile is 1 x 1)", CLI::Range(0.0f, 10.0f))
      ->capture_default_str();
  addOption(c, "--scale", o.scale, "Tiling scale S: the height table repeats S times per tile",
            CLI::Range(1e-3f, 1e3f))
      ->capture_default_str();
  addOption(c, "--octaves", o.octaves, "Octaves of the procedural noise", CLI::Range(1, 12))
      ->capture_default_str();
  addOption(c, "--seed", o.seed, "Seed of the procedural noise")->capture_default_str();
  addOption(c, "--theta-v", o.thetaV, "View angles in degrees, comma separated")
      ->delimiter(',')
      ->capture_default_str();
  addOption(c, "--theta-l", o.thetaL, "Light polar angle in degrees", CLI::Range(0.0f, 90.0f))
      ->capture_default_str();
  addOption(c, "--phi", o.phi, "phi_V - phi_L in degrees", CLI::Range(-360.0f, 360.0f))
      ->capture_default_str();
  addChoice(c, "--component", o.component,
            "Terms of the local model: " + choiceList<Component>("|"));
  addOption(c, "--phong", o.phong, "Phong exponent of the specular component",
            CLI::Range(0.0f, 10000.0f))
      ->capture_default_str();
  addChoice(c, "--format", o.format, choiceList<TableFormat>("|"));
  addOption(c, "--normalize", o.normalize,
            "Scale so that bump at the first theta_V equals this (the paper used 128)");
  addOption(c, "--samples", o.samples, "Samples per view azimuth", CLI::Range(16, 1 << 24))
      ->capture_default_str();
  addOption(c, "--azimuths", o.azimuths, "View azimuths averaged", CLI::Range(1, 4096))
      ->capture_default_str();
  addChoice(c, "--variant", o.variant,
            "Redistribution maps: " + choiceList<RedistributionVariant>("|"));
  addOption(c, "--cache-dir", o.cacheDir,
            "Table cache folder (default $MESO_CACHE_DIR, $XDG_CACHE_HOME/meso or ~/.cache/meso)");
  c->add_flag("--no-cache", o.noCache, "Build the tables without reading or writing the cache");
  c->add_flag("--shadows", o.shadows,
              "Relief self-shadowing: shadow rays in displacement, the traced shadowing factor in "
              "redistribution and brdf "
              "(SCENE: the scene's render.shadows is used)");
  addOption(c, "--shadow-rays", o.shadowRays,
            "--shadows: visible hits per view slice of the shadowing table (0: the renderer's)",
            CLI::Range(0, 1 << 22));
  addOption(c, "--environment", o.environment,
            "Light the patch by an environment instead of --theta-l/--phi: a latitude-longitude "
            "map (any format OpenImageIO reads, its top row towards the patch's normal) or "
            "'uniform' (a uniform white sky; ./uniform for a file of that name)");
  addOption(c, "--environment-rotation", o.environmentRotation,
            "--environment: turn of the map about the patch's normal, degrees",
            CLI::Range(-360.0f, 360.0f))
      ->capture_default_str();
  addOption(c, "--light-samples", o.lightSamples,
            "--environment: directions per sample point, shared by the four renderers",
            CLI::Range(1, kMaxSampleLights))
      ->capture_default_str();
  addOption(c, "--phi-v-bins", o.phiVBins,
            "View-azimuth slices of the tables (0: 1, the paper's average over azimuths, which "
            "suits a light turning with the view; with --environment 16, the renderer's, since a "
            "fixed environment sees the relief's own azimuths)",
            CLI::Range(0, 64))
      ->capture_default_str();
}

// The environment of --environment, its up axis the patch's normal +z.
EnvironmentMap patchEnvironment(const ConsistencyCommandOptions& o, uint64_t memoryLimitBytes) {
  EnvironmentDecl decl;
  decl.loc.file = "--environment";
  if (o.environment != "uniform") decl.file = o.environment;
  decl.rotation = o.environmentRotation;
  decl.up = Vec3(0.0f, 0.0f, 1.0f);
  return EnvironmentMap::load(decl, memoryLimitBytes);
}

CLI::App* addConsistencyOptions(CLI::App& cli, ConsistencyCommandOptions& o) {
  CLI::App* c = cli.add_subcommand("consistency",
                                   "Becker & Max's Figure 6 for any relief: area-averaged "
                                   "intensity of a flat periodic patch for "
                                   "bump, redistribution, brdf and displacement at each theta_V; "
                                   "given a SCENE, the same for the "
                                   "whole scene: each renderer against a full-displacement "
                                   "reference, per object and band of rows");
  addOption(c, "scene", o.scene,
            "Scene file (TOML): compare renderers on the whole scene instead of the patch",
            CLI::ExistingFile);
  addSetOption(c, o.set);
  addOption(c, "--bands", o.bands, "SCENE: bands of image rows", CLI::Range(1, 4096))
      ->capture_default_str();
  addOption(c, "--reference-dicing", o.referenceDicing,
            "SCENE: dicing rate of the displacement reference, pixels", CLI::Range(0.01f, 100.0f))
      ->capture_default_str();
  addOption(c, "--reference-spp", o.referenceSpp,
            "SCENE: samples per pixel of the reference (0: the scene's)", CLI::Range(0, 65536))
      ->capture_default_str();
  addChoices(c, "--algorithms", o.algorithms,
             "SCENE: renderers compared with the reference, comma separated");
  addPatchOptions(c, o);
  return c;
}

void runSceneConsistency(const ConsistencyCommandOptions& o, const RunContext& context) {
  if (!o.environment.empty())
    throw Error(
        "--environment: the patch's light; a SCENE is lit by its own [[lights]] (an environment "
        "there is a light of type \"environment\")");
  const Scene scene = loadScene(o.scene, setOverrides(o.set), context.memoryLimitBytes);
  SceneConsistencyOptions so;
  so.memoryLimitBytes = context.memoryLimitBytes;
  so.algorithms = o.algorithms;
  so.bands = o.bands;
  so.referenceDicing = o.referenceDicing;
  so.referenceSpp = o.referenceSpp;
  so.cancel = &interruptRequested();
  so.onRender = [](const std::string& what) {
    std::fprintf(stderr, "meso: consistency: rendering %s\n", what.c_str());
  };
  SceneConsistencyReport report;
  try {
    report = sceneConsistency(scene, so);
  } catch (const Interrupted&) {
    throw RenderInterrupted();
  }
  std::fputs(formatSceneConsistency(report, o.format).c_str(), stdout);
  std::fprintf(stderr,
               "meso: worst: %s in %s, %.2f%% from the reference; reference (dicing %g px) moves "
               "%.2f%% when diced at %g px\n",
               report.worstRenderer.c_str(), report.worstRegion.c_str(), 100.0 * report.worst,
               o.referenceDicing, 100.0 * report.referenceChange, 2.0 * o.referenceDicing);
  std::fprintf(stderr, "meso: %s\n", detailVerdict(report, o.referenceDicing).c_str());
  for (const std::string& w : report.warnings)
    std::fprintf(stderr, "meso: warning: %s\n", w.c_str());
  if (report.referenceCoarsened)
    std::fprintf(stderr, "meso: %s\n",
                 coarsenedReferenceWarning(report, o.referenceDicing).c_str());
  else if (report.referenceChange > kConvergedChange)
    std::fprintf(
        stderr,
        "meso: warning: the reference is not converged (%.2f%% change over one halving of dicing); "
        "lower --reference-dicing\n",
        100.0 * report.referenceChange);
}

void runConsistency(const ConsistencyCommandOptions& o, const RunContext& context) {
  if (!o.scene.empty()) return runSceneConsistency(o, context);
  if (!o.set.empty())
    throw Error("--set: expected a SCENE (the patch without one has no scene keys)");
  const std::optional<EnvironmentMap> environment =
      o.environment.empty() ? std::nullopt
                            : std::optional(patchEnvironment(o, context.memoryLimitBytes));
  for (float t : o.thetaV)
    if (!(t >= 0.0f && t < 90.0f))
      throw Error(
          "--theta-v: expected angles in [0, 90) degrees (at 90 the view runs along the "
          "patch, which shows no area), got " +
          std::to_string(t));
  const ReliefLevelDecl decl = reliefFrom(o);
  const std::unique_ptr<PeriodicRelief> relief = makeTileRelief(decl, context.memoryLimitBytes);
  TableSettings settings;
  settings.memoryLimitBytes = context.memoryLimitBytes;
  settings.variant = o.variant;
  settings.shadows = o.shadows;
  const int phiV = o.phiVBins > 0 ? o.phiVBins : (environment ? TableResolution{}.phiVBins : 1);
  settings.histogram.resolution.phiV = phiV;
  // Every view-azimuth slice gets the same number of traced azimuths.
  settings.histogram.azimuths = (settings.histogram.azimuths + phiV - 1) / phiV * phiV;
  if (o.shadowRays > 0) settings.shadowing.raysPerSlice = o.shadowRays;
  const TableCache cache(o.noCache
                             ? std::filesystem::path()
                             : (o.cacheDir.empty() ? TableCache::defaultFolder() : o.cacheDir));
  Warnings warnings;
  const LevelTables tables =
      buildLevelTables(*relief, o.phong, settings, nullptr, cache, &warnings);
  for (const std::string& w : warnings.list())
    std::fprintf(stderr, "meso: warning: %s\n", w.c_str());
  const PeriodicTile tile(*relief, settings.histogram.meshResolution);
  ConsistencySettings s;
  s.thetaL = radians(o.thetaL);
  s.phi = radians(o.phi);
  s.component = o.component;
  s.phong = o.phong;
  s.samplesPerAzimuth = o.samples;
  s.azimuths = o.azimuths;
  s.shadows = o.shadows;
  s.environment = environment ? &*environment : nullptr;
  s.lightSamples = o.lightSamples;
  std::vector<ConsistencyRow> rows;
  for (float t : o.thetaV) rows.push_back(measureConsistency(*relief, tile, tables, radians(t), s));
  const std::string table = formatConsistency(rows, o.format, o.normalize);
  std::fputs(table.c_str(), stdout);
}

}  // namespace

std::unique_ptr<Command> makeConsistencyCommand(CLI::App& cli) {
  return std::make_unique<OptionsCommand<ConsistencyCommandOptions>>(cli, addConsistencyOptions,
                                                                     runConsistency);
}

}  // namespace meso::app
