// Reading a control mesh: an OBJ ground of N x N unit quads with uv (as tools/terrain_mesh.py
// writes it, made in memory here), parsed and checked into a ControlMesh (parseControlMesh), and
// the limit surface made from it. Usage: build/tools/bench_mesh [--benchmark_filter=...]
#include "meso/geometry/limit_surface.h"
#include "meso/scene/mesh_io.h"

#include "bench_main.h"

#include <benchmark/benchmark.h>

#include <string>

namespace {

std::string groundObj(int n) {
  std::string s;
  s.reserve(static_cast<size_t>(n + 1) * (n + 1) * 40 + static_cast<size_t>(n) * n * 40);
  const int h = n / 2;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
      s += "v " + std::to_string(i - h) + " 0 " + std::to_string(j - h) + "\n";
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) s += "vt " + std::to_string(i) + " " + std::to_string(j) + "\n";
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int a = i * (n + 1) + j + 1, b = a + 1, c = a + n + 2, d = a + n + 1;
      for (int k : {a, b, c, d})
        s += (k == a ? "f " : " ") + std::to_string(k) + "/" + std::to_string(k);
      s += "\n";
    }
  return s;
}

// Arg: N (the ground has N^2 faces).
void BM_ParseObjGround(benchmark::State& state) {
  const std::string text = groundObj(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(meso::parseControlMesh(text, "ground.obj"));
  state.counters["faces"] = static_cast<double>(state.range(0) * state.range(0));
  state.counters["MB"] = static_cast<double>(text.size()) / 1e6;
}
BENCHMARK(BM_ParseObjGround)->Arg(160)->Arg(640)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_LimitSurfaceOfGround(benchmark::State& state) {
  const meso::ControlMesh mesh =
      meso::parseControlMesh(groundObj(static_cast<int>(state.range(0))), "ground.obj");
  for (auto _ : state)
    benchmark::DoNotOptimize(meso::LimitSurface(mesh, meso::SubdivisionScheme::Bilinear));
}
BENCHMARK(BM_LimitSurfaceOfGround)->Arg(640)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

MESO_BENCHMARK_MAIN()
