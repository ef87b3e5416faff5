#include "meso/render/relief_levels.h"

#include "meso/core/error.h"
#include "meso/core/hash.h"

#include <algorithm>
#include <cmath>

namespace meso {

std::unique_ptr<HeightSource> makeHeightSource(const ReliefLevelDecl& d) {
  if (d.source == "noise")
    return std::make_unique<FractalNoise>(d.octaves, d.lacunarity, d.gain, d.seed);
  try {
    return std::make_unique<HeightTable>(HeightTable::load(d.height, d.periodic));
  } catch (const Error& e) {
    if (d.loc.line > 0) throw Error(d.loc, "relief", e.what());
    throw;
  }
}

ReliefLevel makeReliefLevel(const ReliefLevelDecl& d) {
  ReliefLevel level;
  level.source = makeHeightSource(d);
  level.amplitude = d.amplitude;
  level.scale = d.scale;
  level.freqPerU = d.freq > 0.0f ? d.freq : level.source->highestFrequency() * d.scale;
  level.midlevel = d.midlevel ? *d.midlevel : level.source->meanHeight();
  return level;
}

uint64_t TileRelief::fingerprint() const {
  Hasher h;
  h.value(level_.source->fingerprint()).value(level_.amplitude).value(level_.scale);
  if (lengthPerU_ != 1.0f) h.value(lengthPerU_);  // unit-metric keys as before
  return h.digest();
}

namespace {
// Owns a level and shows it as a tile.
class OwningTileRelief : public PeriodicRelief {
 public:
  explicit OwningTileRelief(ReliefLevel level) : level_(std::move(level)), tile_(level_) {}
  float height(float x, float y) const override { return tile_.height(x, y); }
  Vec2 gradient(float x, float y) const override { return tile_.gradient(x, y); }
  uint64_t fingerprint() const override { return tile_.fingerprint(); }

 private:
  ReliefLevel level_;
  TileRelief tile_;
};
}  // namespace

void buildSlopePyramids(MaterialRelief& relief) {
  for (ReliefLevel& level : relief.levels) {
    if (level.pyramid) continue;
    if (const auto* table = dynamic_cast<const HeightTable*>(level.source.get())) {
      level.pyramid = std::make_shared<SlopePyramid>(*table);
      continue;
    }
    int n = 1;
    while (n < 4.0f * level.source->highestFrequency() && n < 2048) n *= 2;
    level.pyramid = std::make_shared<SlopePyramid>(*level.source, n, n, true);
  }
}

std::unique_ptr<PeriodicRelief> makeTileRelief(const ReliefLevelDecl& decl) {
  return std::make_unique<OwningTileRelief>(makeReliefLevel(decl));
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
  t.variant = q.variant == "separable" ? RedistributionVariant::Separable : RedistributionVariant::Conditional;
  return t;
}

MetricPosition MaterialRelief::metricAt(float lengthPerU) const {
  MetricPosition p;
  const int n = static_cast<int>(metrics.size());
  if (n <= 1 || !(lengthPerU > 0.0f) || !std::isfinite(lengthPerU)) return p;
  if (lengthPerU <= metrics.front().lengthPerU) return p;
  if (lengthPerU >= metrics.back().lengthPerU) {
    p.k0 = p.k1 = p.nearest = n - 1;
    return p;
  }
  int k = 0;
  while (k + 2 < n && metrics[k + 1].lengthPerU <= lengthPerU) ++k;
  p.k0 = k;
  p.k1 = k + 1;
  p.w = std::log(lengthPerU / metrics[k].lengthPerU) / std::log(metrics[k + 1].lengthPerU / metrics[k].lengthPerU);
  p.w = std::clamp(p.w, 0.0f, 1.0f);
  p.nearest = p.w < 0.5f ? p.k0 : p.k1;
  return p;
}

std::vector<float> metricClasses(float lo, float hi, float stepOctaves) {
  if (!(lo > 0.0f) || !std::isfinite(lo) || !std::isfinite(hi) || hi < lo) return {1.0f};
  if (hi / lo < 1.001f) return {std::sqrt(lo * hi)};
  const double octaves = std::log2(static_cast<double>(hi) / lo);
  const int steps = std::max(1, static_cast<int>(std::ceil(octaves / std::max(stepOctaves, 1e-3f) - 1e-6)));
  std::vector<float> out;
  for (int k = 0; k <= steps; ++k)
    out.push_back(static_cast<float>(lo * std::exp2(octaves * k / steps)));
  return out;
}

namespace {

// The tables of every level for one metric class, finest first in the build (each coarser BRDF
// integrates the finer one), stored coarsest first.
MetricTables buildMetricTables(const MaterialRelief& r, const Material& material, float lengthPerU,
                               const TableCache& cache, std::vector<std::string>* warnings,
                               const TableSettings& settings, const SpecularLobe* lobe, int* built, int* loaded,
                               double* seconds) {
  const size_t n = r.levels.size();
  std::vector<LevelTables> reversed;
  for (size_t k = 0; k < n; ++k) {
    const TileRelief tile(r.levels[n - 1 - k], lengthPerU);
    reversed.push_back(buildLevelTables(tile, material.phong, settings, k == 0 ? nullptr : &reversed.back(),
                                        cache, warnings, k == 0 ? lobe : nullptr));
    const LevelTables& t = reversed.back();
    (t.fromCache ? *loaded : *built) += 1;
    *seconds += t.seconds;
  }
  MetricTables m;
  m.lengthPerU = lengthPerU;
  for (size_t k = 0; k < n; ++k) m.levels.push_back(std::move(reversed[n - 1 - k]));
  return m;
}

}  // namespace

MaterialRelief buildMaterialRelief(const Material& material, const TableCache& cache,
                                   std::vector<std::string>* warnings, const TableSettings& settings,
                                   std::vector<float> lengthsPerU) {
  MaterialRelief r;
  for (const ReliefLevelDecl& d : material.relief) r.levels.push_back(makeReliefLevel(d));
  const size_t n = r.levels.size();
  if (material.ndf.present) {
    const ReliefLevel* finest = n > 0 ? &r.levels.back() : nullptr;
    float angle = 0.0f;
    std::unique_ptr<Ndf> ndf = makeNdf(material.ndf, finest ? finest->source.get() : nullptr,
                                       finest ? finest->scale : 1.0f, finest ? finest->amplitude : 0.0f, &angle);
    // Octave 0 continues just below the finest level's shortest wavelength (16 cells per unit of u
    // on a material without relief), unless the scene says otherwise.
    const float base = material.ndf.scale > 0.0f ? material.ndf.scale : (finest ? 2.0f * finest->freqPerU : 16.0f);
    r.synthesis = buildSynthesisLevel(material.ndf, std::move(ndf), base, angle, finest ? finest->source.get() : nullptr,
                                      finest ? finest->scale : 1.0f, finest ? finest->amplitude : 0.0f);
  }
  const SpecularLobe lobe = r.synthesis ? r.synthesis->lobe() : SpecularLobe{};
  std::erase_if(lengthsPerU, [](float l) { return !(l > 0.0f) || !std::isfinite(l); });
  if (lengthsPerU.empty()) lengthsPerU.push_back(1.0f);
  std::sort(lengthsPerU.begin(), lengthsPerU.end());
  lengthsPerU.erase(std::unique(lengthsPerU.begin(), lengthsPerU.end()), lengthsPerU.end());
  if (n == 0) return r;
  for (float l : lengthsPerU)
    r.metrics.push_back(buildMetricTables(r, material, l, cache, warnings, settings, r.synthesis ? &lobe : nullptr,
                                          &r.tablesBuilt, &r.tablesFromCache, &r.tablesSeconds));
  return r;
}

}  // namespace meso
