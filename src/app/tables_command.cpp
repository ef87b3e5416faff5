#include "tables_command.h"

#include "cli_options.h"
#include "command.h"
#include "memory_estimates.h"
#include "scene_options.h"

#include "meso/appearance/material_tables.h"
#include "meso/appearance/table_plots.h"
#include "meso/core/atomic_file.h"
#include "meso/core/image_io.h"
#include "meso/core/timer.h"
#include "meso/render/render_context.h"
#include "meso/scene/scene_parser.h"

#include <cstdio>

namespace meso::app {
namespace {

CLI::App* addTablesOptions(CLI::App& cli, TablesCommandOptions& o) {
  CLI::App* t = cli.add_subcommand(
      "tables",
      "Build (or load from the cache) the appearance tables of the scene's relief levels; print "
      "build time, "
      "size and cache hit/miss per level as CSV; plot histograms and BRDF slices as PNG");
  addOption(t, "scene", o.scene, "Scene file")->required();
  addSetOption(t, o.set);
  addOption(t, "-o,--out-dir", o.outDir, "Folder for the plots")->capture_default_str();
  t->add_flag("--no-plots", o.noPlots, "Only build and report");
  return t;
}

void runTables(const TablesCommandOptions& o, const RunContext& context) {
  Scene scene = loadScene(o.scene, setOverrides(o.set));
  // Every table a render of the scene may read, whatever its algorithm: a scene set to bump or
  // displacement builds none of its own (render_context.cpp), but `--algorithm auto` would.
  scene.render.algorithm = Algorithm::Auto;
  std::vector<std::string> memoryWarnings;
  checkRenderMemory(scene, context.memoryLimitBytes, memoryWarnings, false);
  if (!o.noPlots) createOutputFolder(o.outDir, "-o");
  // The same tables a render of the scene builds: every material objects use, one set per metric
  // class their surfaces need (docs/metric.md).
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(scene, times, false, !o.noPlots);
  for (const std::string& w : ctx.warnings) std::fprintf(stderr, "meso: warning: %s\n", w.c_str());
  std::printf(
      "material,level,metric_length_per_u,source,amplitude,scale,freq_per_u,bands,cache,seconds,"
      "bytes\n");
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
        std::printf("%s,%zu,%g,%s,%g,%g,%g,%s,%s,%.3f,%zu\n", material.name.c_str(), i + 1,
                    relief.metrics[k].lengthPerU, choiceName(d.source), relief.levels[i].amplitude,
                    relief.levels[i].scale, relief.levels[i].freqPerU, bands.c_str(),
                    t.fromCache ? "hit" : "miss", t.seconds, t.bytes);
        if (o.noPlots) continue;
        std::string stem = material.name + "_level" + std::to_string(i + 1);
        if (relief.metrics.size() > 1) stem += "_metric" + std::to_string(k + 1);
        writePngPreview(o.outDir / (stem + "_histogram.png"), plotHistogram(t.distr));
        writePngPreview(o.outDir / (stem + "_brdf.png"), plotBrdf(t.brdf));
      }
  }
  if (!o.noPlots) std::fprintf(stderr, "meso: plots in %s\n", o.outDir.string().c_str());
}

class TablesCommand : public Command {
 public:
  explicit TablesCommand(CLI::App& cli) {
    app_ = addTablesOptions(cli, options_);
    addMemoryLimit();
  }

 private:
  void execute(const RunContext& context) override { runTables(options_, context); }
  TablesCommandOptions options_;
};

}  // namespace

std::unique_ptr<Command> makeTablesCommand(CLI::App& cli) {
  return std::make_unique<TablesCommand>(cli);
}

}  // namespace meso::app
