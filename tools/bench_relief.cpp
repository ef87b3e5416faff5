// Benchmarks of the relief lookups on the per-sample path: quadratic bump derivatives (Becker & Max
// 1993, section 2.2) on a 512 x 512 table, Schilling's filtered slope/roughness pyramid lookup, and
// the one-off builders. Run: ./build/tools/bench_relief
#include "meso/core/rng.h"
#include "meso/relief/band_split.h"
#include "meso/relief/blinn_normal.h"
#include "meso/relief/fractal_noise.h"
#include "meso/relief/height_table.h"
#include "meso/relief/level_frames.h"
#include "meso/relief/slope_pyramid.h"

#include "bench_main.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

namespace {

using namespace meso;

constexpr int kSize = 512;
constexpr size_t kPoints = 1 << 14;  // pre-drawn inputs, cycled: the RNG is not timed

HeightTable randomTable(BumpDerivativeMethod m) {
  Rng rng(1);
  std::vector<float> t(static_cast<size_t>(kSize) * kSize);
  for (float& v : t) v = rng.uniform();
  return HeightTable(kSize, kSize, std::move(t), HeightTableOptions{true, m});
}

const std::vector<Vec2>& points() {
  static const std::vector<Vec2> p = [] {
    Rng rng(2);
    std::vector<Vec2> v(kPoints);
    for (Vec2& x : v) x = Vec2(rng.uniform(), rng.uniform());
    return v;
  }();
  return p;
}

void derivativeLookups(benchmark::State& state, BumpDerivativeMethod m) {
  const HeightTable table = randomTable(m);
  const std::vector<Vec2>& p = points();
  size_t i = 0;
  Vec2 sum(0.0f);
  for (auto _ : state) {
    sum += table.gradient(p[i++ & (kPoints - 1)]);
  }
  benchmark::DoNotOptimize(sum);
}

void BM_QuadraticDerivative(benchmark::State& state) {
  derivativeLookups(state, BumpDerivativeMethod::Quadratic);
}
BENCHMARK(BM_QuadraticDerivative);

void BM_CentralDifferenceDerivative(benchmark::State& state) {
  derivativeLookups(state, BumpDerivativeMethod::CentralDifference);
}
BENCHMARK(BM_CentralDifferenceDerivative);

// Successive lookups 0.37 texel apart along a scanline: the compute cost without cache misses.
void BM_QuadraticDerivativeCoherent(benchmark::State& state) {
  const HeightTable table = randomTable(BumpDerivativeMethod::Quadratic);
  const float step = 0.37f / kSize;
  Vec2 p(0.0f, 0.3f), sum(0.0f);
  for (auto _ : state) {
    sum += table.gradient(p);
    p.x += step;
    if (p.x > 1.0f) p.x -= 1.0f;
  }
  benchmark::DoNotOptimize(sum);
}
BENCHMARK(BM_QuadraticDerivativeCoherent);

void BM_PyramidLookup(benchmark::State& state) {
  const SlopePyramid pyramid(randomTable(BumpDerivativeMethod::Quadratic));
  // Footprints from a tenth of a texel to the whole tile, log-uniform, random orientation.
  Rng rng(3);
  std::vector<Vec2> dx(kPoints), dy(kPoints);
  for (size_t k = 0; k < kPoints; ++k) {
    const float w = std::exp2(-3.3f + 12.3f * rng.uniform()), a = 6.283f * rng.uniform();
    dx[k] = w * Vec2(std::cos(a), std::sin(a));
    dy[k] = (0.2f + 0.8f * rng.uniform()) * w * Vec2(-std::sin(a), std::cos(a));
  }
  const std::vector<Vec2>& p = points();
  size_t i = 0;
  float sum = 0.0f;
  for (auto _ : state) {
    const size_t k = i++ & (kPoints - 1);
    const SlopeSample s = pyramid.lookup(p[k], dx[k], dy[k]);
    sum += s.mean.x + s.roughness.a;
  }
  benchmark::DoNotOptimize(sum);
}
BENCHMARK(BM_PyramidLookup);

void BM_NoiseGradient(benchmark::State& state) {
  const FractalNoise noise(4, 2.0f, 0.5f, 1);
  const std::vector<Vec2>& p = points();
  size_t i = 0;
  Vec2 sum(0.0f);
  for (auto _ : state) sum += noise.gradient(p[i++ & (kPoints - 1)]);
  benchmark::DoNotOptimize(sum);
}
BENCHMARK(BM_NoiseGradient);

void BM_LevelFramesThreeLevels(benchmark::State& state) {
  const HeightTable a = randomTable(BumpDerivativeMethod::Quadratic);
  const FractalNoise b(3, 2.0f, 0.5f, 2);
  const HeightLevel levels[3] = {HeightLevel::make(a, 0.1f, 1.0f),
                                 HeightLevel::make(b, 0.02f, 8.0f),
                                 HeightLevel::make(a, 0.005f, 64.0f)};
  const SurfaceFrame limit{Vec3(1.2f, 0.1f, 0.0f), Vec3(0.3f, 0.9f, 0.1f),
                           glm::normalize(Vec3(-0.1f, -0.1f, 1.0f))};
  const std::vector<Vec2>& p = points();
  size_t i = 0;
  float sum = 0.0f;
  for (auto _ : state) sum += levelFrames(limit, levels, p[i++ & (kPoints - 1)]).frames[3].N.z;
  benchmark::DoNotOptimize(sum);
}
BENCHMARK(BM_LevelFramesThreeLevels);

void BM_BuildPyramid512(benchmark::State& state) {
  const HeightTable table = randomTable(BumpDerivativeMethod::Quadratic);
  for (auto _ : state) {
    SlopePyramid p(table);
    benchmark::DoNotOptimize(p.levels());
  }
}
BENCHMARK(BM_BuildPyramid512)->Unit(benchmark::kMillisecond);

void BM_SplitBands512ThreeLevels(benchmark::State& state) {
  const HeightTable table = randomTable(BumpDerivativeMethod::Quadratic);
  for (auto _ : state) {
    std::vector<HeightBand> bands = splitBands(table, 3);
    benchmark::DoNotOptimize(bands.data());
  }
}
BENCHMARK(BM_SplitBands512ThreeLevels)->Unit(benchmark::kMillisecond);

void BM_LoadTableSpectralFrequency512(benchmark::State& state) {
  const HeightTable source = randomTable(BumpDerivativeMethod::Quadratic);
  for (auto _ : state) {
    HeightTable t(kSize, kSize, source.texels());
    benchmark::DoNotOptimize(t.highestFrequency());
  }
}
BENCHMARK(BM_LoadTableSpectralFrequency512)->Unit(benchmark::kMillisecond);

}  // namespace

MESO_BENCHMARK_MAIN()
