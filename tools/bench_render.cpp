// Benchmarks of the renderer's per-sample work that bench_appearance and bench_tessellation leave
// out: BRDF lookups in the coherent order of neighbouring pixels, the inverse and partial
// redistribution maps (Becker & Max 1993 section 3; the partial map of e3 < T < e4), and Embree
// closest hits on displaced micropolygons for incoherent rays and for camera rays at each dicing
// rate that `meso trade` sweeps. (Random-order BRDF and R_theta lookups: bench_appearance;
// camera rays at dicing rate 1: bench_tessellation.)
// Run: ./build/tools/bench_render
#include "meso/appearance/level_tables.h"
#include "meso/core/rng.h"
#include "meso/geometry/adaptive_tessellation.h"
#include "meso/geometry/ray_scene.h"
#include "meso/scene/camera.h"

#include "bench_main.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <vector>

namespace {

using namespace meso;

// Two crossed octaves of ripples, periodic on the unit tile.
struct Ripples2 : PeriodicRelief {
  static constexpr float kA = 0.03f;
  float height(float x, float y) const override {
    return kA * (std::cos(2 * kPi * (x + 0.25f * y)) + 0.4f * std::sin(2 * kPi * (3 * y - x)));
  }
  Vec2 gradient(float x, float y) const override {
    const float c = kA * 2 * kPi;
    const float s1 = std::sin(2 * kPi * (x + 0.25f * y)), c2 = std::cos(2 * kPi * (3 * y - x));
    return {c * (-s1 - 0.4f * c2), c * (-0.25f * s1 + 1.2f * c2)};
  }
  uint64_t fingerprint() const override { return 0x7e4d'0001; }
};

const LevelTables& tables() {
  static const LevelTables t = buildLevelTables(Ripples2(), 30.0f, TableSettings{}, nullptr,
                                                TableCache{std::filesystem::path()}, nullptr);
  return t;
}

// Angles along one scanline: theta_V and theta_L drift slowly, as between neighbouring pixels.
void BM_BrdfLookupCoherent(benchmark::State& state) {
  const BrdfTable& b = tables().brdf;
  float sum = 0.0f, t = 0.0f;
  for (auto _ : state) {
    t += 1e-4f;
    if (t > 1.0f) t = 0.0f;
    const BrdfTable::Value v = b.lookup(0.2f + 1.2f * t, 0.9f - 0.5f * t, 0.3f + 2.5f * t);
    sum += v.diffuse + v.specular;
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_BrdfLookupCoherent);

void BM_RedistributionToBump(benchmark::State& state) {
  const Redistribution& r = tables().redistribution;
  Rng rng(3);
  float sum = 0.0f;
  for (auto _ : state) {
    const NormalAngles n =
        r.toBump(1.5f * rng.uniform(), {0.5f * rng.uniform(), 6.0f * rng.uniform() - 3.0f});
    sum += n.thetaN + n.phi;
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_RedistributionToBump);

// n' = R_thetaV(R_thetaW^-1(n)): two maps and theta_W per sample of partial displacement.
void BM_RedistributionPartial(benchmark::State& state) {
  const Redistribution& r = tables().redistribution;
  Rng rng(4);
  float sum = 0.0f;
  for (auto _ : state) {
    const NormalAngles n = r.partial(1.5f * rng.uniform(), rng.uniform(),
                                     {0.5f * rng.uniform(), 6.0f * rng.uniform() - 3.0f});
    sum += n.thetaN + n.phi;
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_RedistributionPartial);

// --- Embree on displaced micropolygons ---

// A closed torus (major radius 1, minor 0.4) as nu x nv quads.
ControlMesh torus(int nu, int nv) {
  ControlMesh mesh;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const float a = 2.0f * kPi * i / nu, b = 2.0f * kPi * j / nv, r = 1.0f + 0.4f * std::cos(b);
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

// Fine relief along the limit normal (0.015 units), the kind meso displaces near the camera.
struct Bumps : VertexDisplacement {
  Vec3 offset(int, Vec2, const SurfacePoint& sp) const override {
    const Vec3 p = 40.0f * sp.P;
    return 0.015f * std::sin(p.x) * std::sin(p.y) * std::sin(p.z) * sp.N;
  }
  float bound() const override { return 0.015f; }
};

const Camera& camera() {
  static const Camera c(
      CameraSettings{Vec3(0.0f, 1.6f, 2.4f), Vec3(0.0f), Vec3(0, 1, 0), 40.0f, 640, 360, 4});
  return c;
}
const ScreenMetric& screen() { return camera().screen(); }

struct DisplacedScene {
  AdaptiveTessellation tessellation;
  RayScene rays;
};

// One scene per dicing rate (x 100), built on first use.
const DisplacedScene& displaced(int ratePercent) {
  static std::map<int, std::unique_ptr<DisplacedScene>> scenes;
  static const LimitSurface surface{torus(48, 24), SubdivisionScheme::CatmullClark};
  std::unique_ptr<DisplacedScene>& s = scenes[ratePercent];
  if (!s) {
    static const Bumps bumps;
    DicingSettings dicing;
    dicing.dicingRate = static_cast<float>(ratePercent) / 100.0f;
    s = std::make_unique<DisplacedScene>();
    s->tessellation = tessellateAdaptive(surface, screen(), dicing, FaceDicing{}, &bumps);
    s->rays.addMesh(s->tessellation.mesh, s->tessellation.grids);
    s->rays.commit();
  }
  return *s;
}

// Rays from random points on a sphere of radius 3 towards random points near the torus: no two
// consecutive rays share a BVH path, as for secondary rays and samples spread over a pixel
// footprint.
void BM_IncoherentRays(benchmark::State& state) {
  const DisplacedScene& s = displaced(100);
  Rng rng(5);
  int64_t hits = 0;
  for (auto _ : state) {
    const float z = 2.0f * rng.uniform() - 1.0f, a = 2.0f * kPi * rng.uniform(),
                r = std::sqrt(1.0f - z * z);
    const Vec3 origin = 3.0f * Vec3(r * std::cos(a), z, r * std::sin(a));
    const float b = 2.0f * kPi * rng.uniform();
    const Vec3 target(std::cos(b), 0.3f * (rng.uniform() - 0.5f), std::sin(b));
    RayHit hit;
    hits += s.rays.intersect(Ray{origin, glm::normalize(target - origin)}, hit);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["hit_fraction"] =
      static_cast<double>(hits) / static_cast<double>(state.iterations());
  state.counters["micropolygons"] = static_cast<double>(s.tessellation.stats.micropolygons);
}
BENCHMARK(BM_IncoherentRays);

// Camera rays through the 640x360 pixel centres; argument: dicing rate x 100 (meso trade's sweep).
void BM_CameraRaysByDicingRate(benchmark::State& state) {
  const DisplacedScene& s = displaced(static_cast<int>(state.range(0)));
  const Camera& c = camera();
  const ScreenMetric& m = c.screen();
  int64_t rays = 0;
  for (auto _ : state) {
    for (int y = 0; y < m.height; ++y)
      for (int x = 0; x < m.width; ++x) {
        RayHit hit;
        benchmark::DoNotOptimize(s.rays.intersect(c.generateRay(x + 0.5f, y + 0.5f), hit));
      }
    rays += int64_t(m.width) * m.height;
  }
  state.SetItemsProcessed(rays);
  state.counters["micropolygons"] = static_cast<double>(s.tessellation.stats.micropolygons);
}
BENCHMARK(BM_CameraRaysByDicingRate)
    ->Arg(400)
    ->Arg(200)
    ->Arg(50)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

MESO_BENCHMARK_MAIN()
