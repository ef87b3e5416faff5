#include "tables_command.h"

#include "cli_options.h"
#include "command.h"
#include "external_program.h"
#include "memory_estimates.h"
#include "scene_options.h"

#include "meso/appearance/material_tables.h"
#include "meso/appearance/table_plots.h"
#include "meso/core/atomic_file.h"
#include "meso/core/timer.h"
#include "meso/render/render_context.h"
#include "meso/scene/scene_parser.h"

#include <fmt/format.h>

#include <cstdio>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#ifndef MESO_PLOT_TABLES_SCRIPT
#define MESO_PLOT_TABLES_SCRIPT "tools/plot_tables.py"
#endif

namespace meso::app {
namespace {

CLI::App* addTablesOptions(CLI::App& cli, TablesCommandOptions& o) {
  CLI::App* t = cli.add_subcommand(
      "tables",
      "Build (or load from the cache) the appearance tables of the scene's relief levels; print "
      "build time, "
      "size and cache hit/miss per level as CSV; plot histograms and BRDF slices (PNG, drawn with "
      "matplotlib from CSVs beside them)");
  addOption(t, "scene", o.scene, "Scene file")->required();
  addSetOption(t, o.set);
  addOption(t, "-o,--out-dir", o.outDir, "Folder for the plots and their CSVs")
      ->capture_default_str();
  t->add_flag("--no-plots", o.noPlots, "Only build and report");
  return t;
}

// The PNGs of `plots` (CSV, PNG, CSV, PNG, ...) drawn by tools/plot_tables.py (matplotlib); the
// CSVs stay the source, so a missing plotter costs the pictures only, with a note on how to draw
// them.
void plot(const std::vector<std::string>& plots, const std::filesystem::path& outDir) {
  const std::string script = MESO_PLOT_TABLES_SCRIPT;
  if (plots.empty() || runPythonScript(script, plots)) {
    std::fprintf(stderr, "meso: plots in %s\n", outDir.string().c_str());
    return;
  }
  for (size_t i = 1; i < plots.size(); i += 2) {
    std::error_code ignored;
    std::filesystem::remove(plots[i], ignored);  // an earlier run's plot would not match its CSV
  }
  std::fprintf(stderr,
               "meso: warning: tables not plotted (needs python3 with matplotlib: apt-get install "
               "python3-matplotlib); their CSVs are in %s; to plot them: python3 %s %s ...\n",
               outDir.string().c_str(), script.c_str(), plots.front().c_str());
}

// The theta_V rows the BRDF and self-shadowing tables were built on, in degrees ("0-89" for
// every row; render.tables.frame_views).
std::string viewRowsText(const BrdfTable& brdf) {
  if (brdf.numThetaV() == 0) return "none";
  const ViewRows& r = brdf.viewRows();
  const int first = r.all() ? 0 : r.first, last = r.all() ? brdf.numThetaV() - 1 : r.last;
  return fmt::format("{:.3g}-{:.3g}", brdf.thetaV(first) * 180.0f / kPi,
                     brdf.thetaV(last) * 180.0f / kPi);
}

void runTables(const TablesCommandOptions& o, const RunContext& context) {
  Scene scene = loadScene(o.scene, setOverrides(o.set), context.memoryLimitBytes);
  // Every table a render of the scene may read, whatever its algorithm: a scene set to bump or
  // displacement builds none of its own (render_context.cpp), but `--algorithm auto` would.
  scene.render.algorithm = Algorithm::Auto;
  const double reserved = checkRenderMemory(scene, context.memoryLimitBytes, false);
  if (!o.noPlots) createOutputFolder(o.outDir, "-o");
  // The same tables a render of the scene builds: every material objects use, one set per metric
  // class their surfaces need (docs/metric.md).
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(scene, times,
                                                 {.buildFrame = false,
                                                  .keepHistograms = !o.noPlots,
                                                  .memoryLimitBytes = context.memoryLimitBytes,
                                                  .reservedBytes = reserved,
                                                  .dices = false});
  for (const std::string& w : ctx.warnings.list())
    std::fprintf(stderr, "meso: warning: %s\n", w.c_str());
  std::vector<std::string> plots;  // CSV, PNG, CSV, PNG, ...
  std::printf(
      "material,level,metric_length_per_u,source,amplitude,scale,freq_per_u,bands,theta_v_rows,"
      "cache,seconds,bytes\n");
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    const Material& material = scene.materials[m];
    const MaterialRelief& relief = ctx.reliefs[m];
    for (size_t k = 0; k < relief.metrics.size(); ++k)
      for (size_t i = 0; i < relief.levels.size(); ++i) {
        const LevelTables& t = relief.tables(i, static_cast<int>(k));
        const ReliefLevelDecl& d = material.relief[i];
        // An image's bands as first-last/count (1-based), e.g. 1-4/7; "all" for a whole relief.
        const std::string bands = d.bandCount > 1 ? std::to_string(d.bandFirst + 1) + "-" +
                                                        std::to_string(d.bandLast + 1) + "/" +
                                                        std::to_string(d.bandCount)
                                                  : "all";
        std::printf("%s,%zu,%g,%s,%g,%g,%g,%s,%s,%s,%.3f,%zu\n", material.name.c_str(), i + 1,
                    relief.metrics[k].lengthPerU, choiceName(d.source), relief.levels[i].amplitude,
                    relief.levels[i].scale, relief.levels[i].freqPerU, bands.c_str(),
                    viewRowsText(t.brdf).c_str(), t.fromCache ? "hit" : "miss", t.seconds, t.bytes);
        if (o.noPlots) continue;
        std::string stem = material.name + "_level" + std::to_string(i + 1);
        if (relief.metrics.size() > 1) stem += "_metric" + std::to_string(k + 1);
        for (const auto& [kind, csv] : {std::pair{"_histogram", histogramCsv(t.distr)},
                                        std::pair{"_brdf", brdfCsv(t.brdf)}}) {
          const std::filesystem::path file = o.outDir / (stem + kind + ".csv");
          writeFileAtomically(file, csv);
          plots.push_back(file.string());
          plots.push_back((o.outDir / (stem + kind + ".png")).string());
        }
      }
  }
  if (!o.noPlots) plot(plots, o.outDir);
}

}  // namespace

std::unique_ptr<Command> makeTablesCommand(CLI::App& cli) {
  return std::make_unique<OptionsCommand<TablesCommandOptions>>(cli, addTablesOptions, runTables);
}

}  // namespace meso::app
