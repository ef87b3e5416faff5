// Becker & Max 1993, section 4.3: a height image split into band-limited levels.
#include "meso/scene/relief_bands.h"

#include "meso/core/error.h"
#include "meso/relief/band_split.h"
#include "meso/relief/height_table.h"

#include <algorithm>

namespace meso {

std::vector<ReliefLevelDecl> expandImageBands(const ReliefLevelDecl& d, int maxLevels,
                                              uint64_t memoryLimitBytes) {
  if (d.source != ReliefSource::Image || d.bands == 1 || d.bandCount > 1) return {d};
  BandPlan plan;
  try {
    plan = planBands(HeightTable::load(d.height, d.periodic, memoryLimitBytes), d.bands,
                     std::max(maxLevels, 1));
  } catch (const Error& e) {
    if (d.loc.line > 0) throw Error(d.loc, "relief", e.what());
    throw;
  }
  std::vector<ReliefLevelDecl> out;
  for (const BandLevel& l : plan.levels) {
    ReliefLevelDecl level = d;
    level.bandCount = plan.bands;
    level.bandFirst = l.first;
    level.bandLast = l.last;
    if (l.first > 0) level.midlevel.reset();
    // Coupled bands: T follows the coarsest one that shades (cycles per unit of u).
    if (l.transitionFrequency > 0.0f) level.freq = l.transitionFrequency * d.scale;
    out.push_back(std::move(level));
  }
  if (out.size() == 1) out.front().bandCount = 1;  // one level: the image itself
  return out;
}

void expandImageBands(Scene& scene, uint64_t memoryLimitBytes) {
  for (Material& m : scene.materials) {
    std::vector<ReliefLevelDecl> levels;
    for (size_t k = 0; k < m.relief.size(); ++k) {
      // One level at least for each later relief table.
      const int budget = kMaxMaterialReliefLevels - static_cast<int>(levels.size()) -
                         static_cast<int>(m.relief.size() - 1 - k);
      for (ReliefLevelDecl& d : expandImageBands(m.relief[k], budget, memoryLimitBytes))
        levels.push_back(std::move(d));
    }
    m.relief = std::move(levels);
  }
}

}  // namespace meso
