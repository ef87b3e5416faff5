#include "meso/appearance/level_tables.h"

#include "meso/appearance/class_derivation.h"
#include "meso/core/check.h"
#include "meso/core/timer.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace meso {
namespace {

uint64_t tableKey(const PeriodicRelief& relief, float phong, const TableSettings& s,
                  const uint64_t* finerKey, const SpecularLobe* lobe,
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
  if (finerKey)
    hash.value(*finerKey);
  else if (lobe)
    hash.string("lobe").value(lobe->fingerprint);
  else
    hash.value(phong);
  // A derived class's tables are not its traced ones: keyed by the tile they derive from.
  if (derivation) hash.string("derived").value(derivation->tileKey);
  if (!s.views.all()) hash.string("views").value(s.views.first).value(s.views.last);
  return hash.digest();
}

BrdfTable brdfFor(const VisibleNormalHistogram& distr, float phong, const TableSettings& s,
                  const BrdfTable* finer, const SpecularLobe* lobe) {
  if (finer) return BrdfTable::fromFinerLevel(distr, s.brdf, *finer, s.views);
  return lobe ? BrdfTable::fromDistribution(distr, s.brdf, *lobe, s.views)
              : BrdfTable::fromDistribution(distr, s.brdf, phong, s.views);
}

// The self-shadowing factor of a level, from the cache or traced in the periodic tile.
ShadowingTable shadowingFor(const PeriodicRelief& relief, const VisibleNormalHistogram& layout,
                            float phong, const TableSettings& s, uint64_t levelKey,
                            const TableCache& cache, Warnings* warnings,
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
  if (warnings) warnings->add(warning);
  ShadowingTable table;
  if (cached && ShadowingTable::fromData(*cached, r, table) &&
      table.numPhiV() == layout.resolution().phiV &&
      table.numThetaV() == (layout.resolution().thetaV - 1) * std::max(r.thetaVRefine, 1) + 1) {
    table.setViewRows(s.views);
    return table;
  }
  const ShadowingTable* tileTable = derivation ? &derivation->tile().shadowing : nullptr;
  if (tileTable && !tileTable->empty()) {
    table = deriveShadowing(*tileTable, derivation->map, layout, r, s.views);
  } else {
    const PeriodicTile tile(relief, std::max(s.histogram.meshResolution, 1));
    table = ShadowingTable::trace(relief, tile, layout, s.histogram, r, phong,
                                  s.histogram.seed + 7919, s.views);
  }
  warning.clear();
  cache.store(key, table.toData(), &warning);
  if (warnings) warnings->add(warning);
  return table;
}

// A level between the two phases of its build: its histogram (and self-shadowing factor) loaded or
// traced, its BRDF not yet integrated.
struct PendingLevel {
  uint64_t key = 0;
  VisibleNormalHistogram distr{HistogramResolution{}};
  std::vector<float> brdfData;  // the cached BRDF, when the histogram came from the cache
  bool fromCache = false;
  size_t bytes = 0;
  TableCache::Lock lock;  // from a miss until the tables are stored: one build per key
  ShadowingTable shadowing;
  double shadowingSeconds = 0.0, seconds = 0.0;
  Warnings warnings;
};

// Phase one, in job order: the cached tables, or the key's lock until they are stored. A chain
// takes its locks finest first, one level after the other, as every chain that shares keys with
// it does (a coarser level's key holds its finer level's): builders that share tables (processes,
// or materials of one scene) never wait for each other's locks in a cycle.
void loadOrLock(const LevelJob& job, const TableCache& cache, PendingLevel& p) {
  Timer timer;
  p.distr = VisibleNormalHistogram(job.settings.histogram.resolution);
  std::string warning;
  std::optional<std::vector<float>> cached = cache.loadOrLock(p.key, &warning, &p.lock);
  p.warnings.add(warning);
  const size_t histogramSize = p.distr.numBins();  // the cache holds masses, then the BRDF
  if (cached && cached->size() > histogramSize &&
      p.distr.fromData(std::span<const float>(*cached).first(histogramSize))) {
    p.brdfData.assign(cached->begin() + static_cast<std::ptrdiff_t>(histogramSize), cached->end());
    p.fromCache = true;
  }
  // What the cache holds (or would): masses, then the BRDF.
  p.bytes = cached ? cached->size() * sizeof(float) : 0;
  p.seconds += timer.seconds();
}

// Phase two, every level at once: the histogram (unless cached) and the self-shadowing factor,
// which need no other level's tables.
void traceHistogram(const LevelJob& job, float phong, const TableCache& cache, PendingLevel& p) {
  Timer timer;
  const TableSettings& settings = job.settings;
  const ClassDerivation* derivation = job.derivation;
  if (!p.fromCache)
    p.distr = derivation
                  ? deriveHistogram(derivation->tile().distr, derivation->map,
                                    settings.histogram.resolution, settings.histogram.azimuths)
                  : buildVisibleNormalHistogram(*job.relief, settings.histogram);
  if (settings.shadows) {
    Timer shadowTimer;
    const VisibleNormalHistogram layout(p.distr.resolution(), p.distr.thetaVMax(),
                                        VisibleNormalHistogram::LayoutOnly{});
    p.shadowing =
        shadowingFor(*job.relief, layout, phong, settings, p.key, cache, &p.warnings, derivation);
    p.shadowingSeconds = shadowTimer.seconds();
  }
  p.seconds += timer.seconds();
}

// Phase three, finest first: the BRDF (over the finer level's, eq. 1, or the local model), stored
// with the histogram, and the redistribution maps.
LevelTables finishLevel(const LevelJob& job, float phong, const BrdfTable* finer,
                        const TableCache& cache, PendingLevel& p) {
  Timer timer;
  const TableSettings& settings = job.settings;
  VisibleNormalHistogram& distr = p.distr;
  std::vector<float> thetaV(distr.resolution().thetaV);
  for (int k = 0; k < distr.resolution().thetaV; ++k) thetaV[k] = distr.thetaV(k);
  const int phiV = distr.resolution().phiV;
  const size_t brdfSize = BrdfTable::dataSize(settings.brdf, static_cast<int>(thetaV.size()), phiV);
  BrdfTable brdf = p.fromCache && p.brdfData.size() == brdfSize
                       ? BrdfTable::fromData(thetaV, settings.brdf, std::move(p.brdfData), phiV)
                       : brdfFor(distr, phong, settings, finer, finer ? nullptr : job.lobe);
  const bool fromCache = p.fromCache && brdf.data().size() == brdfSize;
  brdf.setViewRows(settings.views);
  if (!fromCache) {  // assembled only to be stored
    std::vector<float> payload = distr.toData(false);
    payload.insert(payload.end(), brdf.data().begin(), brdf.data().end());
    p.bytes = payload.size() * sizeof(float);
    std::string warning;
    cache.store(p.key, payload, &warning);
    p.warnings.add(warning);
  }
  p.lock.unlock();
  Redistribution redistribution(distr, settings.variant);
  distr.dropMeanNormals();
  if (!settings.keepHistograms)
    distr = VisibleNormalHistogram(distr.resolution(), distr.thetaVMax(),
                                   VisibleNormalHistogram::LayoutOnly{});
  return LevelTables{std::move(distr),
                     std::move(redistribution),
                     std::move(brdf),
                     std::move(p.shadowing),
                     p.shadowingSeconds,
                     p.key,
                     fromCache,
                     p.seconds + timer.seconds(),
                     p.bytes};
}

void appendWarnings(Warnings& from, Warnings* to) {
  if (to) to->append(std::move(from));
}

}  // namespace

LevelTables buildLevelTables(const PeriodicRelief& relief, float phong,
                             const TableSettings& settings, const LevelTables* finer,
                             const TableCache& cache, Warnings* warnings, const SpecularLobe* lobe,
                             const ClassDerivation* derivation) {
  const LevelJob job{&relief, settings, -1, lobe, derivation};
  PendingLevel p;
  p.key = tableKey(relief, phong, settings, finer ? &finer->key : nullptr, lobe, derivation);
  loadOrLock(job, cache, p);
  traceHistogram(job, phong, cache, p);
  LevelTables t = finishLevel(job, phong, finer ? &finer->brdf : nullptr, cache, p);
  appendWarnings(p.warnings, warnings);
  return t;
}

std::vector<LevelTables> buildLevelChain(std::span<const LevelJob> jobs, float phong,
                                         const TableCache& cache, Warnings* warnings) {
  const size_t n = jobs.size();
  std::vector<PendingLevel> pending(n);
  for (size_t i = 0; i < n; ++i) {
    const LevelJob& job = jobs[i];
    MESO_DCHECK(job.finer < static_cast<int>(i), "a level's finer level is built before it");
    pending[i].key = tableKey(*job.relief, phong, job.settings,
                              job.finer >= 0 ? &pending[job.finer].key : nullptr,
                              job.finer >= 0 ? nullptr : job.lobe, job.derivation);
  }
  // Isolated: while its thread waits for its own inner loops it takes no task from outside the
  // chain. It holds its levels' locks from the first phase to the store, and a task of another
  // chain (another class or material) may need one of the same keys: that task would wait for a
  // lock its own thread holds.
  std::vector<LevelTables> out;
  out.reserve(n);
  tbb::this_task_arena::isolate([&] {
    for (size_t i = 0; i < n; ++i) loadOrLock(jobs[i], cache, pending[i]);
    tbb::parallel_for(size_t(0), n,
                      [&](size_t i) { traceHistogram(jobs[i], phong, cache, pending[i]); });
    for (size_t i = 0; i < n; ++i) {
      const int f = jobs[i].finer;
      out.push_back(
          finishLevel(jobs[i], phong, f >= 0 ? &out[f].brdf : nullptr, cache, pending[i]));
    }
  });
  for (PendingLevel& p : pending) appendWarnings(p.warnings, warnings);
  return out;
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
                           Warnings* warnings) {
  const uint64_t key = tileTablesKey(relief, s);
  TileTables t{VisibleNormalHistogram(s.histogram.resolution), {}};
  std::string warning;
  TableCache::Lock buildLock;
  std::optional<std::vector<float>> cached = cache.loadOrLock(key, &warning, &buildLock);
  if (warnings) warnings->add(warning);
  if (!cached || cached->size() != t.distr.numBins() || !t.distr.fromData(*cached)) {
    t.distr = buildVisibleNormalHistogram(relief, s.histogram);
    warning.clear();
    cache.store(key, t.distr.toData(false), &warning);
    if (warnings) warnings->add(warning);
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
