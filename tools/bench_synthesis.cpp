// Benchmarks of fractal NDF synthesis on the per-sample path (Kautz et al. 2001, sections 4 and
// 5.1): one synthesis lookup (turbulence, G, L) at several octave counts, its parts, the shading,
// and the one-off builders. Run: ./build/tools/bench_synthesis
#include "meso/core/rng.h"
#include "meso/synthesis/beckmann_ndf.h"
#include "meso/synthesis/synthesis_sampler.h"
#include "meso/synthesis/synthesized_shading.h"

#include "bench_main.h"

#include <benchmark/benchmark.h>

#include <vector>

namespace {

using namespace meso;

constexpr size_t kPoints = 1 << 14;  // pre-drawn inputs, cycled: the RNG is not timed

const std::vector<Vec2>& points() {
  static const std::vector<Vec2> p = [] {
    Rng rng(2);
    std::vector<Vec2> v(kPoints);
    for (Vec2& x : v) x = Vec2(100.0f * rng.uniform(), 100.0f * rng.uniform());
    return v;
  }();
  return p;
}

const SynthesisSampler& sampler() {
  static const BeckmannNdf ndf(0.3f, 0.1f);
  static const SynthesisSampler s(ndf);
  return s;
}

// One synthesis lookup: normal at (uv, c) = L(G(turbulence(uv, c))). Arg: octave count c.
void BM_SynthesisLookup(benchmark::State& state) {
  const SynthesisSampler& s = sampler();
  const float c = static_cast<float>(state.range(0));
  size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(s.normalAtCount(points()[k++ & (kPoints - 1)], c));
  }
}
BENCHMARK(BM_SynthesisLookup)->Arg(1)->Arg(3)->Arg(6)->Arg(12);

void BM_Turbulence(benchmark::State& state) {
  const SynthesisSampler& s = sampler();
  const float c = static_cast<float>(state.range(0));
  size_t k = 0;
  for (auto _ : state)
    benchmark::DoNotOptimize(s.turbulence().evaluate(points()[k++ & (kPoints - 1)], c));
}
BENCHMARK(BM_Turbulence)->Arg(1)->Arg(6);

void BM_CdfAndTable(benchmark::State& state) {  // G and L for given turbulence values
  const SynthesisSampler& s = sampler();
  size_t k = 0;
  for (auto _ : state) {
    const Vec2 t = 0.004f * points()[k++ & (kPoints - 1)] - 0.2f;
    benchmark::DoNotOptimize(s.table().lookup(s.cdf().G(t, 3.3f)));
  }
}
BENCHMARK(BM_CdfAndTable);

void BM_ShadeSynthesized(benchmark::State& state) {
  const SynthesisSampler& s = sampler();
  const Vec3 N(0, 0, 1), T(1, 0, 0), V = glm::normalize(Vec3(0.3f, 0.1f, 1.0f)),
                                     L = glm::normalize(Vec3(-0.4f, 0.2f, 1.0f));
  size_t k = 0;
  for (auto _ : state) {
    const Vec3 m = s.normalAtCount(points()[k++ & (kPoints - 1)], 6.0f);
    benchmark::DoNotOptimize(shadeSynthesized(s.ndf(), N, T, V, L, m));
  }
}
BENCHMARK(BM_ShadeSynthesized);

void BM_BuildSampler(benchmark::State& state) {
  const BeckmannNdf ndf(0.3f);
  for (auto _ : state) {
    SynthesisSampler s(ndf);
    benchmark::DoNotOptimize(&s);
  }
}
BENCHMARK(BM_BuildSampler)->Unit(benchmark::kMillisecond)->Iterations(2);

void BM_BuildTable(benchmark::State& state) {
  const BeckmannNdf ndf(0.3f);
  for (auto _ : state) {
    NormalLookupTable t(ndf);
    benchmark::DoNotOptimize(&t);
  }
}
BENCHMARK(BM_BuildTable)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

MESO_BENCHMARK_MAIN()
