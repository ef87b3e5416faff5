// Becker & Max 1993, Figure 2: a material's table sets, finest level first (material_tables.h).
#include "meso/appearance/material_tables.h"

#include "meso/core/math.h"
#include "meso/core/progress.h"
#include "meso/relief/height_table.h"

#include <tbb/collaborative_call_once.h>
#include <tbb/parallel_for.h>

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <tuple>

namespace meso {

void buildSlopePyramids(MaterialRelief& relief) {
  for (ReliefLevel& level : relief.levels) {
    // Solid relief has no (u, v) to filter over: bump draws its exact Blinn normals.
    if (level.pyramid || level.solid) continue;
    if (const auto* table = dynamic_cast<const HeightTable*>(level.source.get())) {
      level.pyramid = std::make_shared<SlopePyramid>(*table);
      continue;
    }
    int n = 1;
    while (n < 4.0f * level.source->highestFrequency() && n < 2048) n *= 2;
    level.pyramid = std::make_shared<SlopePyramid>(*level.source, n, n, true);
  }
}

TableSettings tableSettings(const TableResolution& q) {
  TableSettings t;
  t.histogram.resolution = {q.thetaVBins, q.thetaNBins, q.phiBins, q.phiVBins};
  // Every view-azimuth slice gets the same number of traced azimuths.
  t.histogram.azimuths = (q.azimuths + q.phiVBins - 1) / q.phiVBins * q.phiVBins;
  t.histogram.raysPerView = q.raysPerView;
  t.histogram.meshResolution = q.meshResolution;
  t.brdf.thetaL = q.brdfThetaL;
  t.brdf.phi = q.brdfPhi;
  t.variant = q.variant;
  t.deriveClasses = q.deriveClasses;
  t.shadowing.raysPerSlice = q.shadowRays;
  return t;
}

MetricPosition MaterialRelief::metricAt(const MetricClass& m) const {
  MetricPosition p;
  const int n = static_cast<int>(metrics.size());
  if (n <= 1 || !(m.lengthPerU > 0.0f) || !std::isfinite(m.lengthPerU)) return p;
  // The nearest shape, then the run of classes with that shape (sorted by length).
  int best = 0;
  float bestD = std::numeric_limits<float>::infinity();
  for (int k = 0; k < n; ++k) {
    const MetricShape& s = metrics[k].shape;
    const float da = std::log2(s.a / m.shape.a), db = s.b - m.shape.b;
    const float d = da * da + 4.0f * db * db;
    if (d < bestD) bestD = d, best = k;
  }
  int first = best, last = best;
  while (first > 0 && metrics[first - 1].shape == metrics[best].shape) --first;
  while (last + 1 < n && metrics[last + 1].shape == metrics[best].shape) ++last;
  const float l = m.lengthPerU;
  p.k0 = p.k1 = p.nearest = first;
  if (l <= metrics[first].lengthPerU) return p;
  if (l >= metrics[last].lengthPerU) {
    p.k0 = p.k1 = p.nearest = last;
    return p;
  }
  int k = first;
  while (k + 2 <= last && metrics[k + 1].lengthPerU <= l) ++k;
  p.k0 = k;
  p.k1 = k + 1;
  p.w = std::log(l / metrics[k].lengthPerU) /
        std::log(metrics[k + 1].lengthPerU / metrics[k].lengthPerU);
  p.w = std::clamp(p.w, 0.0f, 1.0f);
  p.nearest = p.w < 0.5f ? p.k0 : p.k1;
  return p;
}

namespace {

// The level as its tables trace it: a band that finer bands of its image continue is tabulated as
// their sum.
const ReliefLevel& tabulatedLevel(const ReliefLevel& level) {
  return level.partialSum ? *level.partialSum : level;
}

// Where the metric classes of a material derive their histograms and self-shadowing factors from
// (class_derivation.h): per level, a tile traced as the isotropic class at the geometric middle of
// the classes' lengths, with twice the classes' view-azimuth slices (the derivation interpolates
// between them at each class view's image M^-1 V; with as many slices as the classes, a stretched
// and sheared class's mean visible normal was 1.5 times as far from its traced one).
// Isotropic, the tile has the relief's own slopes and each class's map is the class's own shape;
// at the middle, no class's heights are scaled by more than half the range of lengths (t = tile
// length / class length). A class that is that isotropic class is traced as it is.
struct DerivationTiles {
  float length = 1.0f;                           // the tile's length per unit of u
  TableSettings settings;                        // the tile's
  std::vector<std::optional<TileTables>> tiles;  // per level, built when first needed
  // Per level: its tile is built once, by the first class that needs it; classes that need it
  // meanwhile join that build's parallel loops instead of waiting idle.
  std::unique_ptr<tbb::collaborative_once_flag[]> once;
  std::vector<Warnings> warnings;  // per level: its tile's
  std::vector<uint64_t> keys;      // per level
  // The tile's settings for one level (its traced mesh follows the level: tableMeshResolution).
  TableSettings levelSettings(const ReliefLevel& level) const {
    TableSettings s = settings;
    s.histogram.meshResolution = tableMeshResolution(level, settings.histogram.meshResolution);
    return s;
  }
  bool derives(const MetricClass& m) const {
    return !(m.shape.identity() && m.lengthPerU == length);
  }
};

std::optional<DerivationTiles> planDerivation(const MaterialRelief& r,
                                              const std::vector<MetricClass>& classes,
                                              const TableSettings& s) {
  if (!s.deriveClasses || !s.build || s.histogram.resolution.phiV <= 1 || r.levels.empty())
    return std::nullopt;
  const auto [lo, hi] = std::minmax_element(
      classes.begin(), classes.end(),
      [](const MetricClass& x, const MetricClass& y) { return x.lengthPerU < y.lengthPerU; });
  DerivationTiles d;
  d.length = std::sqrt(lo->lengthPerU * hi->lengthPerU);
  if (classes.size() == 1 && classes[0].shape.identity()) return std::nullopt;
  d.settings = s;
  d.settings.histogram.shape = {};
  HistogramResolution& q = d.settings.histogram.resolution;
  q.phiV *= 2;
  q.thetaV = 2 * q.thetaV - 1;
  d.settings.histogram.azimuths *= 2;
  for (const ReliefLevel& level : r.levels)
    d.keys.push_back(tileTablesKey(TileRelief(tabulatedLevel(level), d.length),
                                   d.levelSettings(tabulatedLevel(level))));
  d.tiles.resize(r.levels.size());
  d.once = std::make_unique<tbb::collaborative_once_flag[]>(r.levels.size());
  d.warnings.resize(r.levels.size());
  return d;
}

// What building one class's tables counted.
struct ClassCount {
  int built = 0, loaded = 0;
  double seconds = 0.0;
  Warnings warnings;
};

// The tables of every level for one metric class, finest first in the build (each coarser BRDF
// integrates the finer one), stored coarsest first. With `derive`, the class's histograms and
// shadowing factors derive from its tiles' (each built once, by the first class that needs it).
MetricTables buildMetricTables(const MaterialRelief& r, const Material& material,
                               const MetricClass& metric, const TableCache& cache,
                               const TableSettings& shapeless, const SpecularLobe* lobe,
                               DerivationTiles* derive, const std::vector<ViewRows>& rows,
                               ClassCount& count, ProgressBar& progress) {
  const float lengthPerU = metric.lengthPerU;
  TableSettings settings = shapeless;
  settings.histogram.shape = metric.shape;
  // A strongly stretched or sheared metric makes the relief's visible normals change fast with
  // the view azimuth: twice the view-azimuth slices there. On a 45-degree shear (b = -1), 16
  // slices left a steep relief 1.6% (redistribution) and 1.1% (BRDF) from displacement in the
  // farthest rows, 32 slices 0.7% and 0.6% (tools/metric-consistency).
  constexpr float kStrongShear = 0.5f, kStrongStretchOctaves = 0.75f;
  HistogramResolution& q = settings.histogram.resolution;
  if (q.phiV > 1 && (std::abs(metric.shape.b) >= kStrongShear ||
                     std::abs(std::log2(metric.shape.a)) >= kStrongStretchOctaves)) {
    settings.histogram.azimuths *= 2;  // a multiple of the slices (tableSettings), as before
    q.phiV *= 2;
  }
  const size_t n = shapeless.build ? r.levels.size() : 0;
  std::vector<std::unique_ptr<TileRelief>> tiles(n);
  std::vector<std::optional<ClassDerivation>> derivations(n);
  std::vector<LevelJob> jobs(n);
  for (size_t k = 0; k < n; ++k) {  // job k: level n - 1 - k (finest first)
    // A band that finer bands of its image continue is tabulated over the level after the image
    // (eq. 1) or as the finest level.
    const size_t index = n - 1 - k;
    const ReliefLevel& level = r.levels[index];
    const size_t finerLevel = level.partialSum ? level.partialSumEnd : n - k;
    const ReliefLevel& traced = tabulatedLevel(level);
    tiles[k] = std::make_unique<TileRelief>(traced, lengthPerU);
    LevelJob& job = jobs[k];
    job.relief = tiles[k].get();
    job.settings = settings;
    if (index < rows.size()) job.settings.views = rows[index];
    job.settings.histogram.meshResolution =
        tableMeshResolution(traced, settings.histogram.meshResolution);
    job.finer = finerLevel < n ? static_cast<int>(n - 1 - finerLevel) : -1;
    job.lobe = job.finer < 0 ? lobe : nullptr;
    if (derive && derive->derives(metric)) {
      derivations[k] = ClassDerivation{
          ClassMap{metric.shape, derive->length / lengthPerU}, derive->keys[index],
          [derive, index, &traced, &material, &shapeless, &cache]() -> const TileTables& {
            tbb::collaborative_call_once(derive->once[index], [&] {
              derive->tiles[index] = buildTileTables(
                  TileRelief(traced, derive->length), material.phong, derive->levelSettings(traced),
                  shapeless.histogram.resolution, cache, &derive->warnings[index]);
            });
            return *derive->tiles[index];
          }};
      job.derivation = &*derivations[k];
    }
  }
  std::vector<LevelTables> built = buildLevelChain(jobs, material.phong, cache, &count.warnings);
  MetricTables m;
  m.lengthPerU = lengthPerU;
  m.shape = metric.shape;
  for (size_t k = 0; k < n; ++k) {
    LevelTables& t = built[n - 1 - k];
    (t.fromCache ? count.loaded : count.built) += 1;
    count.seconds += t.seconds;
    progress.advance();
    m.levels.push_back(std::move(t));
  }
  return m;
}

// The largest rms slope per unit of u (world height per unit of u, the steeper of the two
// directions) of the material's levels.
float steepestSlopePerU(const MaterialRelief& r) {
  float steepest = 0.0f;
  for (const ReliefLevel& level : r.levels)
    steepest = std::max(steepest, static_cast<float>(std::sqrt(levelSlopeMeanSquarePerU(level))));
  return std::isfinite(steepest) ? steepest : 0.0f;
}

// Raises the length of every class on which the relief's tile would be steeper than
// kMaxTableSlope (through the class's stretch and shear), with a warning naming the material.
void clampTableSlopes(const MaterialRelief& r, const std::string& name,
                      std::vector<MetricClass>& classes, Warnings* warnings) {
  const float slopePerU = steepestSlopePerU(r);
  if (!(slopePerU > 0.0f)) return;
  float steepest = 0.0f, shortest = std::numeric_limits<float>::infinity();
  for (MetricClass& m : classes) {
    const float stretch = std::max(m.shape.a, 1.0f / m.shape.a) + std::abs(m.shape.b);
    const float least = slopePerU * stretch / kMaxTableSlope;
    if (!(m.lengthPerU < least) || !std::isfinite(least)) continue;
    steepest = std::max(steepest, slopePerU * stretch / m.lengthPerU);
    shortest = std::min(shortest, m.lengthPerU);
    m.lengthPerU = least;
  }
  if (!(steepest > 0.0f) || !warnings) return;
  warnings->warn(
      "material '{}': on a surface of {:g} world units per unit of u its relief has an rms slope "
      "of {:g} (at most {:g} is tabulated: {:.2f} degrees); its tables are built at that slope "
      "there (is the amplitude meant to be smaller, a mesh far from the origin, or its uv "
      "degenerate?)",
      name, shortest, steepest, kMaxTableSlope, std::atan(kMaxTableSlope) * 180.0f / kPi);
}

}  // namespace

MaterialRelief buildMaterialRelief(
    const Material& material, const TableCache& cache, Warnings* warnings,
    const TableSettings& settings, std::vector<MetricClass> classes, ProgressBar* shared,
    const std::function<std::vector<ViewRows>(const MaterialRelief&)>& levelRows) {
  MaterialRelief r;
  for (const ReliefLevelDecl& d : material.relief) {
    r.levels.push_back(makeReliefLevel(d, settings.memoryLimitBytes));
    const auto* table = dynamic_cast<const HeightTable*>(r.levels.back().source.get());
    if (warnings && table && table->ignoredAlpha() && d.bandFirst == 0)
      warnings->add(d.height.string() +
                    ": its alpha channel is ignored (heights are the luminance of its colour "
                    "channels)");
  }
  const size_t n = r.levels.size();
  linkImageBands(material.relief, r.levels, settings.memoryLimitBytes);
  if (material.ndf.present) {
    const ReliefLevel* finest = n > 0 ? &r.levels.back() : nullptr;
    float angle = 0.0f;
    std::unique_ptr<Ndf> ndf = makeNdf(
        material.ndf, finest ? finest->source.get() : nullptr, finest ? finest->scale : 1.0f,
        finest ? finest->amplitude : 0.0f, &angle, settings.memoryLimitBytes);
    // Octave 0 continues just below the finest level's shortest wavelength (16 cells per unit of u
    // on a material without relief), unless the scene says otherwise.
    const float base =
        material.ndf.scale > 0.0f ? material.ndf.scale : (finest ? 2.0f * finest->freqPerU : 16.0f);
    r.synthesis = buildSynthesisLevel(
        material.ndf, std::move(ndf), base, angle, finest ? finest->source.get() : nullptr,
        finest ? finest->scale : 1.0f, finest ? finest->amplitude : 0.0f);
  }
  const SpecularLobe lobe = r.synthesis ? r.synthesis->lobe() : SpecularLobe{};
  std::erase_if(classes, [](const MetricClass& m) {
    return !(m.lengthPerU > 0.0f) || !std::isfinite(m.lengthPerU);
  });
  if (classes.empty()) classes.push_back({});
  clampTableSlopes(r, material.name, classes, warnings);
  const auto key = [](const MetricClass& m) {
    return std::tuple(m.shape.a, m.shape.b, m.lengthPerU);
  };
  std::sort(classes.begin(), classes.end(),
            [&](const MetricClass& x, const MetricClass& y) { return key(x) < key(y); });
  classes.erase(
      std::unique(classes.begin(), classes.end(),
                  [&](const MetricClass& x, const MetricClass& y) { return key(x) == key(y); }),
      classes.end());
  if (n == 0) return r;
  // Building a table set takes about half a second (minutes at high resolutions or for steep
  // relief), reading one from the cache milliseconds: the bar shows only for the former.
  std::optional<ProgressBar> own;
  if (!shared)
    own.emplace("tables " + material.name,
                static_cast<int64_t>(settings.build ? classes.size() * n : 0), true,
                std::chrono::milliseconds(1000));
  ProgressBar& progress = shared ? *shared : *own;
  std::optional<DerivationTiles> derive = planDerivation(r, classes, settings);
  // Classes at once (each builds its levels at once, then their BRDFs): the same tables, in the
  // same order, whatever the thread count.
  r.metrics.resize(classes.size());
  for (size_t c = 0; c < classes.size(); ++c) {
    r.metrics[c].lengthPerU = classes[c].lengthPerU;
    r.metrics[c].shape = classes[c].shape;
  }
  const std::vector<ViewRows> rows =
      levelRows && settings.build ? levelRows(r) : std::vector<ViewRows>{};
  std::vector<ClassCount> counts(classes.size());
  tbb::parallel_for(size_t(0), classes.size(), [&](size_t c) {
    r.metrics[c] =
        buildMetricTables(r, material, classes[c], cache, settings, r.synthesis ? &lobe : nullptr,
                          derive ? &*derive : nullptr, rows, counts[c], progress);
  });
  if (derive && warnings)
    for (Warnings& w : derive->warnings) warnings->append(std::move(w));
  for (ClassCount& c : counts) {
    if (warnings) warnings->append(std::move(c.warnings));
    r.tablesBuilt += c.built;
    r.tablesFromCache += c.loaded;
    r.tablesSeconds += c.seconds;
  }
  if (own) own->finish();
  return r;
}

}  // namespace meso
