// All appearance tables of one relief level (DESIGN.md section 4): built once, cached on disk, and
// only for levels a scene uses.
#pragma once

#include "meso/appearance/brdf_table.h"
#include "meso/appearance/class_map.h"
#include "meso/appearance/histogram_builder.h"
#include "meso/appearance/redistribution.h"
#include "meso/appearance/shadowing_table.h"
#include "meso/appearance/table_cache.h"
#include "meso/core/memory_budget.h"
#include "meso/core/warnings.h"

#include <functional>
#include <span>
#include <string>
#include <vector>

namespace meso {

struct TableSettings {
  HistogramSettings histogram;
  BrdfResolution brdf;
  // Conditional by default: on the consistency test (Figure 6) the separable maps lose the coupling
  // between tilt and azimuth of visible normals and miss displacement by up to 5% at 60 degrees,
  // the conditional maps by under 0.4% (measured on two reliefs,
  // tests/render/consistency_test.cpp).
  RedistributionVariant variant = RedistributionVariant::Conditional;
  // render.shadows: also trace the relief's self-shadowing factor (ShadowingTable), cached under
  // its own key (the level's key with a shadows flag), so the unshadowed tables keep theirs.
  bool shadows = false;
  ShadowingResolution shadowing;
  // false: build and load no tables at all, for renderers that read none (bump and displacement
  // shade with Blinn normals): only what a frame needs is modelled. Metric classes are still
  // listed.
  bool build = true;
  // false: once a level's other tables are built from its histogram, the histogram keeps only its
  // layout (the renderers read none of its masses): 3 MB less per table set at the default
  // resolution, 28 of the default scene's 126 MB of tables. `meso tables` keeps them for its plots.
  bool keepHistograms = true;
  // render.tables.derive_classes: every metric class of a level but one derives its histograms
  // and self-shadowing factor from that one's traced tile (class_derivation.h) instead of tracing
  // its own; false traces every class. Only tables with view-azimuth slices derive (an average
  // over view azimuths does not map to another class's).
  bool deriveClasses = true;
  // The command's --memory-limit: height and NDF images larger than it allows are refused before
  // they are decoded.
  uint64_t memoryLimitBytes = defaultMemoryLimitBytes();
  // The histogram's theta_V rows on which the level's BRDF and self-shadowing tables are built
  // (its histogram and redistribution tables have every row: redistribution maps from theta_V =
  // 0). Part of the cache key unless every row.
  ViewRows views;
};

// What the metric classes of one level derive from: the histogram (masses) and self-shadowing
// factor of one traced tile.
struct TileTables {
  VisibleNormalHistogram distr{HistogramResolution{}};
  ShadowingTable shadowing;  // empty unless TableSettings::shadows
};

// A metric class whose histogram and self-shadowing factor derive from its level's traced tile.
struct ClassDerivation {
  ClassMap map;          // from the tile's frame to the class's
  uint64_t tileKey = 0;  // identifies the tile's tables: part of the class's cache key
  std::function<const TileTables&()> tile;  // loaded or traced when first called
};

struct LevelTables {
  VisibleNormalHistogram distr;
  Redistribution redistribution;
  BrdfTable brdf;
  ShadowingTable shadowing;       // empty unless TableSettings::shadows
  double shadowingSeconds = 0.0;  // its build or load time (part of `seconds`)
  uint64_t key = 0;  // cache key (also shapes the keys of coarser levels built over this one)
  bool fromCache = false;
  double seconds = 0.0;  // build or load time
  size_t bytes = 0;      // size of the cached payload
};

// Builds (or loads) the tables of a level. `finer` is the next finer level's tables, or nullptr for
// the finest level, whose BRDF uses (L.N) and (H.N)^phong. Warnings (a corrupt cache file that was
// rebuilt, an unwritable cache) are appended to *warnings.
// `lobe` (may be null) replaces (H.N)^phong in the finest level's BRDF.
// `derivation` (may be null): the histogram and self-shadowing factor are derived from a traced
// tile's (the relief and settings' shape then only name the class).
LevelTables buildLevelTables(const PeriodicRelief& relief, float phong,
                             const TableSettings& settings, const LevelTables* finer,
                             const TableCache& cache, Warnings* warnings,
                             const SpecularLobe* lobe = nullptr,
                             const ClassDerivation* derivation = nullptr);

// One level of a chain that buildLevelChain builds, finest first.
struct LevelJob {
  const PeriodicRelief* relief = nullptr;  // as its tables trace it
  TableSettings settings;
  int finer = -1;  // the earlier job whose BRDF this level's integrates (eq. 1), or -1: the finest
  const SpecularLobe* lobe = nullptr;           // as for buildLevelTables (finest level only)
  const ClassDerivation* derivation = nullptr;  // as for buildLevelTables
};

// The tables of every job, as buildLevelTables would build each (the same bits): the histograms
// and self-shadowing factors of all levels at once (no level's depends on another's), then the
// BRDFs finest first, each over its finer level's. Warnings are appended in job order.
std::vector<LevelTables> buildLevelChain(std::span<const LevelJob> jobs, float phong,
                                         const TableCache& cache, Warnings* warnings);

// The cache key of a traced tile's TileTables (relief as traced, settings' histogram and shadows).
uint64_t tileTablesKey(const PeriodicRelief& relief, const TableSettings& settings);
// Loads or traces the histogram (its own cache entry, masses only) and self-shadowing factor of a
// tile, for the classes that derive from it; the factor on the slices of `shadowingLayout`.
TileTables buildTileTables(const PeriodicRelief& relief, float phong, const TableSettings& settings,
                           const HistogramResolution& shadowingLayout, const TableCache& cache,
                           Warnings* warnings);

}  // namespace meso
