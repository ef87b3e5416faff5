// Benchmarks of view-dependent displaced tessellation (shared/DESIGN.md section 5): a Catmull-Clark
// torus seen at 640x360, dicing rate 1 px, smooth analytic displacement. Issue 5's goals on 2
// cores:
// >= 5 M micropolygons/s tessellate+displace, >= 5 M triangles/s BVH build, <= 150 MiB per million
// micropolygons at peak. BM_PeakMemory runs first so that VmHWM starts from the process baseline.
// Run: ./build/tools/bench_tessellation
#include "meso/core/timer.h"
#include "meso/geometry/adaptive_tessellation.h"
#include "meso/geometry/ray_scene.h"
#include "meso/scene/camera.h"

#include "bench_main.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <vector>

namespace {

using namespace meso;

// A torus of major radius 1 and minor radius 0.4 as nu x nv quads, facing outward.
ControlMesh torus(int nu, int nv) {
  ControlMesh mesh;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const float a = 2.0f * kPi * i / nu, b = 2.0f * kPi * j / nv;
      const float r = 1.0f + 0.4f * std::cos(b);
      mesh.positions.emplace_back(r * std::cos(a), 0.4f * std::sin(b), r * std::sin(a));
    }
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const int i1 = (i + 1) % nu, j1 = (j + 1) % nv;
      mesh.faceSizes.push_back(4);
      mesh.faceVertices.insert(mesh.faceVertices.end(),
                               {i * nv + j, i * nv + j1, i1 * nv + j1, i1 * nv + j});
    }
  return mesh;
}

// Smooth relief along the limit normal, 0.02 units at most.
struct Ripples : VertexDisplacement {
  Vec3 offset(int, Vec2, const SurfacePoint& sp) const override {
    const Vec3 p = 12.0f * sp.P;
    return 0.02f * std::sin(p.x) * std::sin(p.y + 0.5f) * std::sin(p.z + 1.0f) * sp.N;
  }
  float bound() const override { return 0.02f; }
};

struct Setup {
  LimitSurface surface{torus(48, 24), SubdivisionScheme::CatmullClark};
  Camera camera{
      CameraSettings{Vec3(0.0f, 1.6f, 2.4f), Vec3(0.0f), Vec3(0, 1, 0), 40.0f, 640, 360, 4}};
  ScreenMetric screen = camera.screen();
  Ripples ripples;
  AdaptiveTessellation tessellate() const {
    return tessellateAdaptive(surface, screen, DicingSettings{}, FaceDicing{}, &ripples);
  }
};

const Setup& setup() {
  static const Setup s;
  return s;
}

size_t meshBytes(const TessellatedMesh& m) {
  return m.positions.size() * sizeof(Vec3) + m.indices.size() * sizeof(uint32_t) +
         m.triangleFace.size() * sizeof(int) + m.cornerSt.size() * sizeof(Vec2);
}

// Peak memory of one frame's geometry: tessellation, then the Embree scene built from it, while
// the mesh stays alive (the renderer needs it at every hit). Argument 1: face interiors as Embree
// grids (the renderer's path), 0: all triangles. VmHWM is only meaningful for the first run in the
// process, so the grid case comes first; the other figures come from sizes and Embree's monitor.
void BM_PeakMemory(benchmark::State& state) {
  const Setup& s = setup();
  const bool useGrids = state.range(0) != 0;
  for (auto _ : state) {
    const double before = peakRssMib();
    const AdaptiveTessellation t = s.tessellate();
    RayScene scene;
    scene.addMesh(t.mesh, useGrids ? t.grids : std::vector<TriangleGrid>{});
    scene.commit();
    const double after = peakRssMib();
    const double millions = static_cast<double>(t.stats.micropolygons) * 1e-6;
    const double mib = 1.0 / (1024.0 * 1024.0);
    state.counters["micropolygons"] = static_cast<double>(t.stats.micropolygons);
    state.counters["VmHWM_MiB_per_M"] = (after - before) / millions;
    state.counters["mesh_MiB_per_M"] = static_cast<double>(meshBytes(t.mesh)) * mib / millions;
    state.counters["embree_peak_MiB_per_M"] =
        static_cast<double>(scene.peakDeviceBytes()) * mib / millions;
    state.counters["embree_final_MiB_per_M"] =
        static_cast<double>(scene.deviceBytes()) * mib / millions;
  }
}
BENCHMARK(BM_PeakMemory)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_TessellateDisplace(benchmark::State& state) {
  const Setup& s = setup();
  size_t micropolygons = 0;
  double rateSeconds = 0.0, evaluateSeconds = 0.0;
  for (auto _ : state) {
    const AdaptiveTessellation t = s.tessellate();
    micropolygons = t.stats.micropolygons;
    rateSeconds += t.stats.rateSeconds;
    evaluateSeconds += t.stats.evaluateSeconds;
    benchmark::DoNotOptimize(t.mesh.positions.data());
  }
  const double n = static_cast<double>(state.iterations());
  state.SetItemsProcessed(static_cast<int64_t>(micropolygons) * state.iterations());
  state.counters["micropolygons"] = static_cast<double>(micropolygons);
  state.counters["rate_ms"] = 1e3 * rateSeconds / n;
  state.counters["evaluate_ms"] = 1e3 * evaluateSeconds / n;
}
BENCHMARK(BM_TessellateDisplace)->Unit(benchmark::kMillisecond)->UseRealTime();

// addMesh (the copy into Embree's buffers) and commit (the BVH build); the device is made outside
// the timing. Argument 1: face interiors as Embree grids, 0: all triangles.
void BM_BuildBvh(benchmark::State& state) {
  const AdaptiveTessellation t = setup().tessellate();
  const std::vector<TriangleGrid> grids = state.range(0) ? t.grids : std::vector<TriangleGrid>{};
  for (auto _ : state) {
    state.PauseTiming();
    auto scene = std::make_unique<RayScene>();
    state.ResumeTiming();
    scene->addMesh(t.mesh, grids);
    scene->commit();
    state.PauseTiming();
    scene.reset();
    state.ResumeTiming();
  }
  state.SetItemsProcessed(static_cast<int64_t>(t.stats.micropolygons) * state.iterations());
  state.counters["triangles"] = static_cast<double>(t.stats.micropolygons);
}
BENCHMARK(BM_BuildBvh)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();

// Closest-hit rate of one thread for camera rays through the 640x360 pixel centres, to weigh the
// grids' smaller memory against their ray rate.
void BM_CameraRays(benchmark::State& state) {
  const Setup& s = setup();
  const AdaptiveTessellation t = s.tessellate();
  RayScene scene;
  scene.addMesh(t.mesh, state.range(0) ? t.grids : std::vector<TriangleGrid>{});
  scene.commit();
  const ScreenMetric& m = s.screen;
  int64_t rays = 0;
  for (auto _ : state) {
    for (int y = 0; y < m.height; ++y)
      for (int x = 0; x < m.width; ++x) {
        RayHit hit;
        benchmark::DoNotOptimize(scene.intersect(s.camera.generateRay(x + 0.5f, y + 0.5f), hit));
      }
    rays += int64_t(m.width) * m.height;
  }
  state.SetItemsProcessed(rays);
}
BENCHMARK(BM_CameraRays)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

MESO_BENCHMARK_MAIN()
