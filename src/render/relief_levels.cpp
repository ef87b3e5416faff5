#include "meso/render/relief_levels.h"

#include "meso/core/error.h"
#include "meso/core/hash.h"

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
  return level;
}

uint64_t TileRelief::fingerprint() const {
  return Hasher().value(level_.source->fingerprint()).value(level_.amplitude).value(level_.scale).digest();
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
  t.histogram.resolution = {q.thetaVBins, q.thetaNBins, q.phiBins};
  t.histogram.azimuths = q.azimuths;
  t.histogram.raysPerView = q.raysPerView;
  t.histogram.meshResolution = q.meshResolution;
  t.brdf.thetaL = q.brdfThetaL;
  t.brdf.phi = q.brdfPhi;
  t.variant = q.variant == "separable" ? RedistributionVariant::Separable : RedistributionVariant::Conditional;
  return t;
}

MaterialRelief buildMaterialRelief(const Material& material, const TableCache& cache,
                                   std::vector<std::string>* warnings, const TableSettings& settings) {
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
  std::vector<LevelTables> reversed;  // finest first: each coarser BRDF integrates the finer one
  for (size_t k = 0; k < n; ++k) {
    const TileRelief tile(r.levels[n - 1 - k]);
    reversed.push_back(buildLevelTables(tile, material.phong, settings, k == 0 ? nullptr : &reversed.back(),
                                        cache, warnings, k == 0 && r.synthesis ? &lobe : nullptr));
    const LevelTables& t = reversed.back();
    (t.fromCache ? r.tablesFromCache : r.tablesBuilt) += 1;
    r.tablesSeconds += t.seconds;
  }
  for (size_t k = 0; k < n; ++k) r.tables.push_back(std::move(reversed[n - 1 - k]));
  return r;
}

}  // namespace meso
