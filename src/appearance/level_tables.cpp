#include "meso/appearance/level_tables.h"

#include "meso/appearance/class_derivation.h"
#include "meso/core/timer.h"

namespace meso {
namespace {

uint64_t tableKey(const PeriodicRelief& relief, float phong, const TableSettings& s,
                  const LevelTables* finer, const SpecularLobe* lobe,
                  const ClassDerivation* derivation) {
  const HistogramSettings& h = s.histogram;
  Hasher hash;
  hash.value(kTableFormatVersion).value(relief.fingerprint());
  hash.value(h.resolution.thetaV).value(h.resolution.thetaN).value(h.resolution.phi);
  hash.value(h.azimuths).value(h.raysPerView).value(h.meshResolution).value(h.seed);
  hash.value(s.brdf.thetaL).value(s.brdf.phi);
  const NormalGrouping& gf = s.brdf.finest;
  const NormalGrouping& gc = s.brdf.coarser;
  if (gf.thetaN != 0.0f || gf.phi != 0.0f || gc.thetaN != 0.0f || gc.phi != 0.0f)
    hash.string("grouping").value(gf.thetaN).value(gf.phi).value(gc.thetaN).value(gc.phi);
  if (h.resolution.phiV != 1)
    hash.string("phiV").value(h.resolution.phiV);  // isotropic keys as before
  if (!h.shape.identity()) hash.string("shape").value(h.shape.a).value(h.shape.b);
  // The finest BRDF depends on the Phong exponent; a coarser one on the finer tables instead.
  if (finer)
    hash.value(finer->key);
  else if (lobe)
    hash.string("lobe").value(lobe->fingerprint);
  else
    hash.value(phong);
  // A derived class's tables are not its traced ones: keyed by the tile they derive from.
  if (derivation) hash.string("derived").value(derivation->tileKey);
  return hash.digest();
}

BrdfTable brdfFor(const VisibleNormalHistogram& distr, float phong, const TableSettings& s,
                  const LevelTables* finer, const SpecularLobe* lobe) {
  if (finer) return BrdfTable::fromFinerLevel(distr, s.brdf, finer->brdf);
  return lobe ? BrdfTable::fromDistribution(distr, s.brdf, *lobe)
              : BrdfTable::fromDistribution(distr, s.brdf, phong);
}

// The self-shadowing factor of a level, from the cache or traced in the periodic tile.
ShadowingTable shadowingFor(const PeriodicRelief& relief, const VisibleNormalHistogram& layout,
                            float phong, const TableSettings& s, uint64_t levelKey,
                            const TableCache& cache, std::vector<std::string>* warnings,
                            const ClassDerivation* derivation) {
  const ShadowingResolution& r = s.shadowing;
  Hasher hash;
  // v6: decided by horizon marches (ShadowingTable::trace), equal to v5's shadow rays to rounding.
  hash.value(levelKey)
      .string("shadows-v6")
      .value(r.thetaL)
      .value(r.phi)
      .value(r.raysPerSlice)
      .value(r.azimuthsPerSlice)
      .value(r.thetaVRefine);
  hash.value(kShadowMaxTiles);
  hash.value(phong);
  const uint64_t key = hash.digest();
  std::string warning;
  TableCache::Lock buildLock;  // from a miss until the table is stored: one build per key
  std::optional<std::vector<float>> cached = cache.loadOrLock(key, &warning, &buildLock);
  if (!warning.empty() && warnings) warnings->push_back(warning);
  ShadowingTable table;
  if (cached && ShadowingTable::fromData(*cached, r, table) &&
      table.numPhiV() == layout.resolution().phiV &&
      table.numThetaV() == (layout.resolution().thetaV - 1) * std::max(r.thetaVRefine, 1) + 1)
    return table;
  const ShadowingTable* tileTable = derivation ? &derivation->tile().shadowing : nullptr;
  if (tileTable && !tileTable->empty()) {
    table = deriveShadowing(*tileTable, derivation->map, layout, r);
  } else {
    const PeriodicTile tile(relief, std::max(s.histogram.meshResolution, 1));
    table =
        ShadowingTable::trace(relief, tile, layout, s.histogram, r, phong, s.histogram.seed + 7919);
  }
  warning.clear();
  cache.store(key, table.toData(), &warning);
  if (!warning.empty() && warnings) warnings->push_back(warning);
  return table;
}

}  // namespace

LevelTables buildLevelTables(const PeriodicRelief& relief, float phong,
                             const TableSettings& settings, const LevelTables* finer,
                             const TableCache& cache, std::vector<std::string>* warnings,
                             const SpecularLobe* lobe, const ClassDerivation* derivation) {
  Timer timer;
  const uint64_t key = tableKey(relief, phong, settings, finer, lobe, derivation);
  VisibleNormalHistogram distr(settings.histogram.resolution);
  std::string warning;
  TableCache::Lock buildLock;  // from a miss until the tables are stored: one build per key
  std::optional<std::vector<float>> cached = cache.loadOrLock(key, &warning, &buildLock);
  if (!warning.empty() && warnings) warnings->push_back(warning);
  const size_t histogramSize = distr.numBins();  // the cache holds masses, then the BRDF
  bool fromCache = false;
  std::vector<float> brdfData;
  if (cached && cached->size() > histogramSize &&
      distr.fromData(std::span<const float>(*cached).first(histogramSize))) {
    brdfData.assign(cached->begin() + static_cast<std::ptrdiff_t>(histogramSize), cached->end());
    fromCache = true;
  }
  // What the cache holds (or would): masses, then the BRDF.
  size_t bytes = cached ? cached->size() * sizeof(float) : 0;
  cached.reset();  // copied out: its memory goes to the tables built next
  if (!fromCache)
    distr = derivation ? deriveHistogram(derivation->tile().distr, derivation->map,
                                         settings.histogram.resolution, settings.histogram.azimuths)
                       : buildVisibleNormalHistogram(relief, settings.histogram);
  std::vector<float> thetaV(distr.resolution().thetaV);
  for (int k = 0; k < distr.resolution().thetaV; ++k) thetaV[k] = distr.thetaV(k);
  const int phiV = distr.resolution().phiV;
  const size_t brdfSize = BrdfTable::dataSize(settings.brdf, static_cast<int>(thetaV.size()), phiV);
  BrdfTable brdf = fromCache && brdfData.size() == brdfSize
                       ? BrdfTable::fromData(thetaV, settings.brdf, std::move(brdfData), phiV)
                       : brdfFor(distr, phong, settings, finer, lobe);
  fromCache = fromCache && brdf.data().size() == brdfSize;
  if (!fromCache) {  // assembled only to be stored
    std::vector<float> payload = distr.toData(false);
    payload.insert(payload.end(), brdf.data().begin(), brdf.data().end());
    bytes = payload.size() * sizeof(float);
    warning.clear();
    cache.store(key, payload, &warning);
    if (!warning.empty() && warnings) warnings->push_back(warning);
  }
  buildLock.unlock();
  Redistribution redistribution(distr, settings.variant);
  distr.dropMeanNormals();
  ShadowingTable shadowing;
  double shadowingSeconds = 0.0;
  if (settings.shadows) {
    Timer shadowTimer;
    shadowing = shadowingFor(relief, distr, phong, settings, key, cache, warnings, derivation);
    shadowingSeconds = shadowTimer.seconds();
  }
  if (!settings.keepHistograms)
    distr = VisibleNormalHistogram(distr.resolution(), distr.thetaVMax(),
                                   VisibleNormalHistogram::LayoutOnly{});
  return LevelTables{std::move(distr),
                     std::move(redistribution),
                     std::move(brdf),
                     std::move(shadowing),
                     shadowingSeconds,
                     key,
                     fromCache,
                     timer.seconds(),
                     bytes};
}

uint64_t tileTablesKey(const PeriodicRelief& relief, const TableSettings& s) {
  const HistogramSettings& h = s.histogram;
  Hasher hash;
  hash.value(kTableFormatVersion).string("tile").value(relief.fingerprint());
  hash.value(h.resolution.thetaV).value(h.resolution.thetaN).value(h.resolution.phi);
  hash.value(h.resolution.phiV).value(h.azimuths).value(h.raysPerView).value(h.meshResolution);
  hash.value(h.seed).value(h.shape.a).value(h.shape.b);
  return hash.digest();
}

TileTables buildTileTables(const PeriodicRelief& relief, float phong, const TableSettings& s,
                           const HistogramResolution& shadowingLayout, const TableCache& cache,
                           std::vector<std::string>* warnings) {
  const uint64_t key = tileTablesKey(relief, s);
  TileTables t{VisibleNormalHistogram(s.histogram.resolution), {}};
  std::string warning;
  TableCache::Lock buildLock;
  std::optional<std::vector<float>> cached = cache.loadOrLock(key, &warning, &buildLock);
  if (!warning.empty() && warnings) warnings->push_back(warning);
  if (!cached || cached->size() != t.distr.numBins() || !t.distr.fromData(*cached)) {
    t.distr = buildVisibleNormalHistogram(relief, s.histogram);
    warning.clear();
    cache.store(key, t.distr.toData(false), &warning);
    if (!warning.empty() && warnings) warnings->push_back(warning);
  }
  buildLock.unlock();
  t.distr.dropMeanNormals();  // derivation reads masses, as from the cache
  // The factor is smooth in V and L, and its theta_V nodes already refine the slices.
  const VisibleNormalHistogram layout(shadowingLayout, t.distr.thetaVMax(),
                                      VisibleNormalHistogram::LayoutOnly{});
  if (s.shadows)
    t.shadowing = shadowingFor(relief, layout, phong, s, key, cache, warnings, nullptr);
  return t;
}

}  // namespace meso
