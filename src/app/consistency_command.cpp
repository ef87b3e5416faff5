#include "consistency_command.h"
#include "scene_options.h"

#include "meso/appearance/table_cache.h"
#include "meso/core/error.h"
#include "meso/core/math.h"
#include "meso/render/consistency.h"
#include "meso/render/integrator.h"
#include "meso/appearance/material_tables.h"
#include "meso/render/local_contrast.h"
#include "meso/render/scene_consistency.h"
#include "meso/scene/scene_parser.h"
#include "render_command.h"

#include <cmath>
#include <cstdio>
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
  char head[200];
  std::snprintf(head, sizeof head,
                "as detailed (local contrast within %g%% of the reference's where its contrast is "
                "at least %g): ",
                100.0 * kContrastTolerance, kReliefContrastFloor);
  if (std::isnan(report.worstContrastRatio)) return head + std::string("no region shows relief");
  std::string failing;
  for (const std::string& r : report.notDetailed) failing += (failing.empty() ? "" : ", ") + r;
  char tail[400];
  std::snprintf(tail, sizeof tail,
                "; worst: %s in %s, contrast ratio %.3f; the reference's contrast moves %.2f%% "
                "when diced at %g px",
                report.worstContrastRenderer.c_str(), report.worstContrastRegion.c_str(),
                report.worstContrastRatio, 100.0 * report.referenceContrastChange,
                2.0 * referenceDicing);
  return head + (failing.empty() ? std::string("every renderer passes") : "fails: " + failing) +
         tail;
}

}  // namespace

void runSceneConsistency(const ConsistencyCommandOptions& o) {
  const Scene scene = loadScene(o.scene, setOverrides(o.set));
  SceneConsistencyOptions so;
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
    std::fprintf(stderr,
                 "meso: WARNING: the reference is not diced as asked: the micropolygon cap "
                 "(render.max_micropolygons) coarsened it, so its change when diced at %g px says "
                 "nothing about its convergence; raise render.max_micropolygons in the scene "
                 "or --reference-dicing\n",
                 2.0 * o.referenceDicing);
  else if (report.referenceChange > 0.01)
    std::fprintf(
        stderr,
        "meso: warning: the reference is not converged (%.2f%% change over one halving of dicing); "
        "lower --reference-dicing\n",
        100.0 * report.referenceChange);
}

void runConsistency(const ConsistencyCommandOptions& o) {
  if (!o.scene.empty()) return runSceneConsistency(o);
  if (!o.set.empty())
    throw Error("--set: expected a SCENE (the patch without one has no scene keys)");
  for (float t : o.thetaV)
    if (!(t >= 0.0f && t < 90.0f))
      throw Error(
          "--theta-v: expected angles in [0, 90) degrees (at 90 the view runs along the "
          "patch, which shows no area), got " +
          std::to_string(t));
  const ReliefLevelDecl decl = reliefFrom(o);
  const std::unique_ptr<PeriodicRelief> relief = makeTileRelief(decl);
  TableSettings settings;
  settings.variant = o.variant;
  settings.shadows = o.shadows;
  if (o.shadowRays > 0) settings.shadowing.raysPerSlice = o.shadowRays;
  const TableCache cache(o.noCache
                             ? std::filesystem::path()
                             : (o.cacheDir.empty() ? TableCache::defaultFolder() : o.cacheDir));
  std::vector<std::string> warnings;
  const LevelTables tables =
      buildLevelTables(*relief, o.phong, settings, nullptr, cache, &warnings);
  for (const std::string& w : warnings) std::fprintf(stderr, "meso: warning: %s\n", w.c_str());
  const PeriodicTile tile(*relief, settings.histogram.meshResolution);
  ConsistencySettings s;
  s.thetaL = radians(o.thetaL);
  s.phi = radians(o.phi);
  s.component = o.component;
  s.phong = o.phong;
  s.samplesPerAzimuth = o.samples;
  s.azimuths = o.azimuths;
  s.shadows = o.shadows;
  std::vector<ConsistencyRow> rows;
  for (float t : o.thetaV) rows.push_back(measureConsistency(*relief, tile, tables, radians(t), s));
  const std::string table = formatConsistency(rows, o.format, o.normalize);
  std::fputs(table.c_str(), stdout);
}

}  // namespace meso::app
