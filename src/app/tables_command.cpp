#include "tables_command.h"

#include "meso/appearance/table_plots.h"
#include "meso/core/image_io.h"
#include "meso/core/timer.h"
#include "meso/render/relief_levels.h"
#include "meso/scene/scene_parser.h"

#include <cstdio>

namespace meso::app {

void runTables(const TablesCommandOptions& o) {
  const Scene scene = loadScene(o.scene);
  const TableCache cache(scene.render.cacheDir.empty() ? TableCache::defaultFolder() : scene.render.cacheDir);
  std::vector<bool> used(scene.materials.size(), false);
  for (const Object& obj : scene.objects) used[obj.material] = true;
  std::printf("material,level,source,amplitude,scale,freq_per_u,cache,seconds,bytes\n");
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    const Material& material = scene.materials[m];
    if (!used[m] || material.relief.empty()) continue;
    std::vector<std::string> warnings;
    const MaterialRelief relief = buildMaterialRelief(material, cache, &warnings, tableSettings(scene.render.tables));
    for (const std::string& w : warnings) std::fprintf(stderr, "meso: warning: %s\n", w.c_str());
    for (size_t i = 0; i < relief.levels.size(); ++i) {
      const LevelTables& t = relief.tables[i];
      std::printf("%s,%zu,%s,%g,%g,%g,%s,%.3f,%zu\n", material.name.c_str(), i + 1, material.relief[i].source.c_str(),
                  relief.levels[i].amplitude, relief.levels[i].scale, relief.levels[i].freqPerU,
                  t.fromCache ? "hit" : "miss", t.seconds, t.bytes);
      if (o.noPlots) continue;
      std::filesystem::create_directories(o.outDir);
      const std::string stem = material.name + "_level" + std::to_string(i + 1);
      writePngPreview(o.outDir / (stem + "_histogram.png"), plotHistogram(t.distr));
      writePngPreview(o.outDir / (stem + "_brdf.png"), plotBrdf(t.brdf));
    }
  }
  if (!o.noPlots) std::fprintf(stderr, "meso: plots in %s\n", o.outDir.string().c_str());
}

}  // namespace meso::app
