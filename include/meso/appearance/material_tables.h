// The tables a material gets (DESIGN.md section 1): its relief levels (declared_levels.h), their
// appearance tables per metric class (coarser over finer as in Figure 2), the synthesis level below
// the finest, slope pyramids and visible heights.
#pragma once

#include "meso/appearance/declared_levels.h"
#include "meso/appearance/level_tables.h"
#include "meso/appearance/metric_classes.h"
#include "meso/appearance/synthesis_level.h"
#include "meso/appearance/visible_height.h"
#include "meso/core/progress.h"
#include "meso/core/warnings.h"
#include "meso/relief/height_source.h"
#include "meso/relief/relief_level.h"
#include "meso/scene/scene.h"

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace meso {

// The tables of every level for one isotropic metric class (docs/metric.md): the relief as seen on
// a surface whose unit of u is lengthPerU world units long.
struct MetricTables {
  float lengthPerU = 1.0f;
  MetricShape shape;                // the area-preserving stretch and shear of the class
  std::vector<LevelTables> levels;  // levels[i] belongs to MaterialRelief::levels[i]
};

// The levels of one material and their tables (coarser tables are built over finer ones as in
// Figure 2), one set per metric class the scene needs.
struct MaterialRelief {
  std::vector<ReliefLevel> levels;
  std::vector<MetricTables> metrics;  // sorted by lengthPerU; one class when the metric is constant
  // None when the renderer reads no tables (TableSettings::build false: bump and displacement).
  const LevelTables& tables(size_t level, int metric = 0) const {
    return metrics[metric].levels[level];
  }
  MetricPosition metricAt(const MetricClass& m) const;
  // metricAt(metricOf(Pu, Pv)), without measuring the metric when there is one class or none
  // (class 0, w 0 either way): the shader asks this for every sample.
  MetricPosition metricAt(const Vec3& Pu, const Vec3& Pv) const {
    return metrics.size() > 1 ? metricAt(metricOf(Pu, Pv)) : MetricPosition{};
  }
  // The level below the finest relief level (or the only one): fractal NDF synthesis, when the
  // material declares [materials.ndf].
  std::unique_ptr<SynthesisLevel> synthesis;
  // Per level, where the hybrid draws it flat (visible_height.h); built once per render context
  // (buildVisibleHeights), empty for the other renderers.
  std::vector<VisibleHeight> visibleHeights;
  int tablesBuilt = 0;
  int tablesFromCache = 0;
  double tablesSeconds = 0.0;
};

// Fills relief.visibleHeights, one per level. Levels after the first ride on the crests of raised
// coarser ones and get crest tables; the first does when its surfaces are curved (it rides on the
// limit surface's own crests), and skips the march on planes.
void buildVisibleHeights(MaterialRelief& relief, bool curvedSurface);

// The library's table settings for a scene's [render.tables].
TableSettings tableSettings(const TableResolution& resolution);

// Builds (or loads) the tables of every level for each metric class (sorted by shape, then length,
// here). Empty means the unit metric only. `progress` (may be null: a bar of the material's own)
// advances by one per table set. `levelRows` (may be empty: every row), given the relief with its
// classes' lengths and shapes in `metrics`, says per level (coarsest first; levels it leaves out
// get every row) on which theta_V rows its BRDF and self-shadowing tables are built
// (TableSettings::views).
MaterialRelief buildMaterialRelief(
    const Material& material, const TableCache& cache, Warnings* warnings,
    const TableSettings& settings = {}, std::vector<MetricClass> classes = {},
    ProgressBar* progress = nullptr,
    const std::function<std::vector<ViewRows>(const MaterialRelief&)>& levelRows = {});

// The steepest rms slope a class's tables are built for (89.4 degrees): beyond it the class's
// length per unit of u is raised until the relief is this steep, with a warning. Tracing a tile
// many periods tall costs minutes per table set (an amplitude of 1e6 took 467 s) and describes a
// bed of needles that no real surface is.
inline constexpr float kMaxTableSlope = 100.0f;

// True when the material has anything for the relief renderers (levels or an NDF).
inline bool hasRelief(const Material& m) { return !m.relief.empty() || m.ndf.present; }

// Builds each level's slope pyramid: a height table's own texels (rounded up to powers of two), or
// a procedural source sampled 4 times per period of its highest frequency (at most 2048 x 2048).
void buildSlopePyramids(MaterialRelief& relief);

}  // namespace meso
