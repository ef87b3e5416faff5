// Benchmarks of the appearance tables: build time of the table set a render builds per level
// (BM_BuildRendererTableSet; docs/tables.md), of a simpler set (one view azimuth, no shadowing),
// and the per-sample lookups of the BRDF and redistribution. Run: ./build/tools/bench_appearance
#include "meso/appearance/level_tables.h"
#include "meso/appearance/material_tables.h"
#include "meso/core/rng.h"

#include "bench_main.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>

namespace {

using namespace meso;

struct Waves : PeriodicRelief {
  float height(float x, float y) const override {
    return 0.04f *
           (std::sin(2 * kPi * x) * std::sin(2 * kPi * y) + 0.5f * std::sin(2 * kPi * (2 * x + y)));
  }
  Vec2 gradient(float x, float y) const override {
    const float c = 0.04f * 2 * kPi;
    return {c * (std::cos(2 * kPi * x) * std::sin(2 * kPi * y) + std::cos(2 * kPi * (2 * x + y))),
            c * (std::sin(2 * kPi * x) * std::cos(2 * kPi * y) +
                 0.5f * std::cos(2 * kPi * (2 * x + y)))};
  }
  uint64_t fingerprint() const override { return 1; }
};

const LevelTables& tables() {
  static const LevelTables t = buildLevelTables(Waves(), 20.0f, TableSettings{}, nullptr,
                                                TableCache{std::filesystem::path()}, nullptr);
  return t;
}

void BM_BuildLevelTablesDefault(benchmark::State& state) {
  for (auto _ : state) {
    LevelTables t = buildLevelTables(Waves(), 20.0f, TableSettings{}, nullptr,
                                     TableCache{std::filesystem::path()}, nullptr);
    benchmark::DoNotOptimize(t.brdf.data().data());
  }
}
BENCHMARK(BM_BuildLevelTablesDefault)->Unit(benchmark::kMillisecond)->Iterations(3);

// The table set a render builds for one relief level at the default scene settings
// (tableSettings of the default render.tables: 16 view azimuths, the self-shadowing table): the
// finest level of a 3-octave fBm (local model) and a coarser level over it (eq. 1), each with its
// shadowing table, on a unit-speed surface. Arg: 0 the finest level, 1 the coarser one.
void BM_BuildRendererTableSet(benchmark::State& state) {
  TableSettings settings = tableSettings(TableResolution{});
  settings.shadows = true;
  ReliefLevelDecl coarse;
  coarse.source = ReliefSource::Noise;
  coarse.octaves = 1, coarse.amplitude = 0.012f, coarse.scale = 50.0f, coarse.seed = 11;
  ReliefLevelDecl fine = coarse;
  fine.firstOctave = 1, fine.octaves = 3;
  const ReliefLevel coarseLevel = makeReliefLevel(coarse), fineLevel = makeReliefLevel(fine);
  const TableCache none{std::filesystem::path()};
  const LevelTables finest =
      buildLevelTables(TileRelief(fineLevel, 16.0f), 20.0f, settings, nullptr, none, nullptr);
  for (auto _ : state) {
    LevelTables t = state.range(0) == 0 ? buildLevelTables(TileRelief(fineLevel, 16.0f), 20.0f,
                                                           settings, nullptr, none, nullptr)
                                        : buildLevelTables(TileRelief(coarseLevel, 16.0f), 20.0f,
                                                           settings, &finest, none, nullptr);
    benchmark::DoNotOptimize(t.brdf.data().data());
  }
}
BENCHMARK(BM_BuildRendererTableSet)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(2);

void BM_BuildLevelTablesFromCache(benchmark::State& state) {
  const auto dir = std::filesystem::temp_directory_path() / "meso_bench_cache";
  const TableCache cache(dir);
  buildLevelTables(Waves(), 20.0f, TableSettings{}, nullptr, cache, nullptr);
  for (auto _ : state) {
    LevelTables t = buildLevelTables(Waves(), 20.0f, TableSettings{}, nullptr, cache, nullptr);
    if (!t.fromCache) state.SkipWithError("cache miss");
    benchmark::DoNotOptimize(t.brdf.data().data());
  }
  std::filesystem::remove_all(dir);
}
BENCHMARK(BM_BuildLevelTablesFromCache)->Unit(benchmark::kMillisecond);

void BM_BrdfLookup(benchmark::State& state) {
  const BrdfTable& b = tables().brdf;
  Rng rng(1);
  float sum = 0;
  for (auto _ : state) {
    const BrdfTable::Value v =
        b.lookup(1.5f * rng.uniform(), 1.5f * rng.uniform(), 3.1f * rng.uniform());
    sum += v.diffuse + v.specular;
  }
  benchmark::DoNotOptimize(sum);
}
BENCHMARK(BM_BrdfLookup);

void BM_RedistributionLookup(benchmark::State& state) {
  const Redistribution& r = tables().redistribution;
  Rng rng(2);
  float sum = 0;
  for (auto _ : state) {
    const NormalAngles n =
        r.toVisible(1.5f * rng.uniform(), {0.5f * rng.uniform(), 6.0f * rng.uniform() - 3.0f});
    sum += n.thetaN + n.phi;
  }
  benchmark::DoNotOptimize(sum);
}
BENCHMARK(BM_RedistributionLookup);

// The same lookups on tables with 16 view-azimuth slices (render.tables.phi_v_bins, the scenes'
// default): 4 view slices and up to 8 CDFs mixed per redistribution, 16 BRDF corners.
const LevelTables& azimuthTables() {
  static const LevelTables t = [] {
    TableSettings s;
    s.histogram.resolution.phiV = 16;
    return buildLevelTables(Waves(), 20.0f, s, nullptr, TableCache{std::filesystem::path()},
                            nullptr);
  }();
  return t;
}

void BM_BrdfLookupViewAzimuth(benchmark::State& state) {
  const BrdfTable& b = azimuthTables().brdf;
  Rng rng(1);
  float sum = 0;
  for (auto _ : state) {
    const BrdfTable::Value v = b.lookup(1.5f * rng.uniform(), 6.2f * rng.uniform(),
                                        1.5f * rng.uniform(), 6.2f * rng.uniform() - 3.1f);
    sum += v.diffuse + v.specular;
  }
  benchmark::DoNotOptimize(sum);
}
BENCHMARK(BM_BrdfLookupViewAzimuth);

void BM_RedistributionLookupViewAzimuth(benchmark::State& state) {
  const Redistribution& r = azimuthTables().redistribution;
  Rng rng(2);
  float sum = 0;
  for (auto _ : state) {
    const NormalAngles n = r.toVisible(1.5f * rng.uniform(), 6.2f * rng.uniform(),
                                       {0.5f * rng.uniform(), 6.0f * rng.uniform() - 3.0f});
    sum += n.thetaN + n.phi;
  }
  benchmark::DoNotOptimize(sum);
}
BENCHMARK(BM_RedistributionLookupViewAzimuth);

}  // namespace

MESO_BENCHMARK_MAIN()
