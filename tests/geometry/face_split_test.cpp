// Faces split where their rate changes (src/geometry/face_split.cpp): crack-free, fewer
// micropolygons where faces straddle the view, the same dicing where they are seen.
#include "geometry/test_meshes.h"
#include "meso/core/error.h"
#include "meso/core/rng.h"
#include "meso/geometry/adaptive_tessellation.h"
#include "meso/geometry/ray_scene.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <utility>
#include <vector>

namespace meso {
namespace {

bool finitePositions(const TessellatedMesh& mesh) {
  return std::all_of(mesh.positions.begin(), mesh.positions.end(), [](Vec3 p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
  });
}

// Rays from inside the closed surface, as Embree's WatertightTest: none may escape.
int escapes(const AdaptiveTessellation& t, bool useGrids, int numRays) {
  RayScene scene;
  useGrids ? scene.addMesh(t.mesh, t.grids) : scene.addMesh(t.mesh);
  scene.commit();
  Rng rng(77);
  int missed = 0;
  for (int i = 0; i < numRays; ++i) {
    const float z = 1.0f - 2.0f * rng.uniform(), phi = 2.0f * kPi * rng.uniform();
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    RayHit hit;
    missed += !scene.intersect(Ray{Vec3(0.0f), Vec3(r * std::cos(phi), r * std::sin(phi), z)}, hit);
  }
  return missed;
}

// Grid hits that report their face and st (TriangleGrid::face) report the mesh's: the sub-quads'
// grids of split faces too. Returns the share of hits in grids that did.
double gridHitsWithTheirOwnSt(const AdaptiveTessellation& t, int numRays) {
  RayScene scene;
  scene.addMesh(t.mesh, t.grids);
  scene.commit();
  Rng rng(78);
  int known = 0, inGrids = 0;
  for (int i = 0; i < numRays; ++i) {
    const float z = 1.0f - 2.0f * rng.uniform(), phi = 2.0f * kPi * rng.uniform();
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    RayHit hit;
    if (!scene.intersect(Ray{Vec3(0.0f), Vec3(r * std::cos(phi), r * std::sin(phi), z)}, hit))
      continue;
    inGrids += std::any_of(t.grids.begin(), t.grids.end(), [&](const TriangleGrid& g) {
      return size_t(hit.triangle) >= g.firstTriangle &&
             size_t(hit.triangle) < g.firstTriangle + 2 * size_t(g.width - 1) * (g.height - 1);
    });
    if (hit.face < 0) continue;
    ++known;
    EXPECT_EQ(hit.face, t.mesh.triangleFace[hit.triangle]) << "ray " << i;
    EXPECT_LT(glm::length(hit.st - t.mesh.patchCoords(hit.triangle, hit.b1, hit.b2)), 1e-5f)
        << "ray " << i;
  }
  std::printf("  %d of %d hits in grids know their face and st\n", known, inGrids);
  return inGrids > 0 ? double(known) / inGrids : 0.0;
}

// The eye close to the +z side of the displaced cube, looking past its corner: faces straddle the
// view's border, and near faces recede steeply in depth.
TEST(FaceSplit, DisplacedClosedSurfacesWithSplitFacesAreWatertight) {
  const ScreenMetric screen = ScreenMetric::lookAt(Vec3(0.4f, 0.3f, 1.9f), Vec3(1.0f, 0.8f, 0.0f),
                                                   Vec3(0, 1, 0), 40.0f, 320, 180);
  const test::WaveDisplacement wave;
  for (DicingMetric metric : {DicingMetric::Isotropic, DicingMetric::Projected})
    for (int n : {1, 3}) {
      const LimitSurface surface(test::refinedCube(n), SubdivisionScheme::CatmullClark);
      DicingSettings settings;
      settings.metric = metric;
      const AdaptiveTessellation t = tessellateAdaptive(surface, screen, settings, {}, &wave);
      std::printf("  %d faces: %d split, %zu micropolygons (%zu off screen), %zu grids\n",
                  surface.numFaces(), t.stats.facesSplit, t.stats.micropolygons,
                  t.stats.offScreenMicropolygons, t.grids.size());
      EXPECT_GT(t.stats.facesSplit, 0);
      EXPECT_TRUE(finitePositions(t.mesh));
      EXPECT_EQ(test::countOpenEdges(t.mesh), 0);  // no cracks, no T-junctions, oriented
      EXPECT_EQ(escapes(t, false, 20000), 0) << "triangles";
      EXPECT_EQ(escapes(t, true, 20000), 0) << "grids";
      EXPECT_GT(gridHitsWithTheirOwnSt(t, 5000), 0.99);
    }
}

// The same view under a cap of a third of what it asks: the cap coarsens the far faces and the far
// sub-quads of split faces by their own distances, and the surface stays closed.
TEST(FaceSplit, CappedSurfacesCoarsenedByDistanceAreWatertight) {
  const ScreenMetric screen = ScreenMetric::lookAt(Vec3(0.4f, 0.3f, 1.9f), Vec3(1.0f, 0.8f, 0.0f),
                                                   Vec3(0, 1, 0), 40.0f, 320, 180);
  const test::WaveDisplacement wave;
  const LimitSurface surface(test::refinedCube(3), SubdivisionScheme::CatmullClark);
  DicingSettings settings;
  const size_t asked = tessellateAdaptive(surface, screen, settings, {}, &wave).stats.micropolygons;
  settings.maxMicropolygons = asked / 3;
  const AdaptiveTessellation t = tessellateAdaptive(surface, screen, settings, {}, &wave);
  std::printf("  %zu asked, %zu capped, %d faces split; as asked nearer than %.3g, up to %.3gx\n",
              asked, t.stats.micropolygons, t.stats.facesSplit, t.stats.coarsenedBeyond,
              t.stats.coarsening);
  EXPECT_GT(t.stats.facesSplit, 0);
  EXPECT_GT(t.stats.coarsening, 1.0f);
  EXPECT_LE(t.stats.micropolygons, settings.maxMicropolygons);
  EXPECT_TRUE(finitePositions(t.mesh));
  EXPECT_EQ(test::countOpenEdges(t.mesh), 0);
  EXPECT_EQ(escapes(t, false, 20000), 0) << "triangles";
  EXPECT_EQ(escapes(t, true, 20000), 0) << "grids";
}

// Edges of the plane [0, n]^2 (z = 0) not used exactly once in each direction, but for its border.
int openInnerEdges(const TessellatedMesh& mesh, float n) {
  std::map<std::pair<uint32_t, uint32_t>, int> uses;  // +1 forward, +16 backward
  for (size_t t = 0; t < mesh.numTriangles(); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = mesh.indices[3 * t + k], b = mesh.indices[3 * t + (k + 1) % 3];
      uses[{std::min(a, b), std::max(a, b)}] += a < b ? 1 : 16;
    }
  const auto onBorder = [&](uint32_t i) {
    const Vec3 p = mesh.positions[i];
    return std::min({p.x, p.y, n - p.x, n - p.y}) < 1e-5f;
  };
  int open = 0;
  for (const auto& [edge, count] : uses)
    open += count != 17 && !(onBorder(edge.first) && onBorder(edge.second));
  return open;
}

struct PlaneDicing {
  AdaptiveTessellation t;
  float legP99 = 0.0f, worstLeg = 0.0f;  // micropolygon legs in view, in pixel footprints
};

PlaneDicing dicePlane(const LimitSurface& surface, const ScreenMetric& screen, bool split) {
  DicingSettings settings;
  settings.splitFaces = split;
  settings.maxEdgeRate = 4096;
  PlaneDicing out{tessellateAdaptive(surface, screen, settings, {}, nullptr)};
  const test::InViewLegs legs = test::inViewLegs(out.t.mesh, screen);
  out.legP99 = legs.p99;
  out.worstLeg = legs.worst;
  return out;
}

// A 2 x 2 ground seen from just above its near edge, looking along it: the near half of the near
// faces lies below the view, and the faces recede steeply. Splitting dices the part out of view
// coarsely and the far part by its own density.
TEST(FaceSplit, PlaneFacesStraddlingTheViewGetFewerMicropolygons) {
  const LimitSurface surface(test::grid(2), SubdivisionScheme::Bilinear);
  const ScreenMetric screen = ScreenMetric::lookAt(Vec3(1.0f, -0.2f, 0.4f), Vec3(1.0f, 2.0f, 0.0f),
                                                   Vec3(0, 0, 1), 40.0f, 160, 90);
  const PlaneDicing whole = dicePlane(surface, screen, false);
  const PlaneDicing split = dicePlane(surface, screen, true);
  std::printf(
      "  whole faces: %zu micropolygons (%zu off screen), legs in view p99 %.3f, max %.3f\n"
      "  split (%d faces): %zu micropolygons (%zu off screen), legs in view p99 %.3f, max %.3f\n",
      whole.t.stats.micropolygons, whole.t.stats.offScreenMicropolygons, whole.legP99,
      whole.worstLeg, split.t.stats.facesSplit, split.t.stats.micropolygons,
      split.t.stats.offScreenMicropolygons, split.legP99, split.worstLeg);
  EXPECT_EQ(whole.t.stats.facesSplit, 0);
  EXPECT_GT(split.t.stats.facesSplit, 0);
  EXPECT_LT(split.t.stats.micropolygons, whole.t.stats.micropolygons / 2);
  EXPECT_LT(split.t.stats.offScreenMicropolygons, whole.t.stats.offScreenMicropolygons / 4);
  // Where it is seen the plane is diced as before: legs at most the dicing rate of 1 footprint
  // (15% for the sampling and the joins of sub-quads of different rates, 16 x 16 of them at most,
  // more at the longest where Bfr joins different rates).
  EXPECT_LE(split.legP99, 1.15f);
  EXPECT_LE(split.worstLeg, 1.5f);
  EXPECT_TRUE(finitePositions(split.t.mesh));
  EXPECT_EQ(openInnerEdges(split.t.mesh, 2.0f), 0);
}

// One unit face wholly in view, from 0.6 to 1.6 units deep: its near part needs about 2.7 times
// the density of its far part, which whole-face dicing gives everywhere.
TEST(FaceSplit, DeepFacesInViewAreDicedByTheirOwnDensity) {
  const LimitSurface surface(test::grid(1), SubdivisionScheme::Bilinear);
  const ScreenMetric screen = ScreenMetric::lookAt(Vec3(0.5f, -0.6f, 0.25f), Vec3(0.5f, 0.5f, 0.0f),
                                                   Vec3(0, 0, 1), 60.0f, 160, 90);
  const PlaneDicing whole = dicePlane(surface, screen, false);
  const PlaneDicing split = dicePlane(surface, screen, true);
  std::printf(
      "  whole face: %zu micropolygons, legs p99 %.3f, max %.3f\n"
      "  split %dx: %zu micropolygons, legs p99 %.3f, max %.3f\n",
      whole.t.stats.micropolygons, whole.legP99, whole.worstLeg, split.t.stats.facesSplit,
      split.t.stats.micropolygons, split.legP99, split.worstLeg);
  EXPECT_EQ(whole.t.stats.offScreenMicropolygons, 0u);
  EXPECT_EQ(split.t.stats.facesSplit, 1);
  EXPECT_LT(split.t.stats.micropolygons, whole.t.stats.micropolygons * 3 / 4);
  EXPECT_LE(split.legP99, 1.15f);  // as above
  EXPECT_LE(split.worstLeg, 1.5f);
  EXPECT_EQ(openInnerEdges(split.t.mesh, 1.0f), 0);
}

// To the extremes: the eye almost on the plane, inside a face's hull, and far away; splits stay
// finite and crack-free.
TEST(FaceSplit, ExtremeViewsStayFiniteAndCrackFree) {
  const LimitSurface surface(test::grid(2), SubdivisionScheme::Bilinear);
  const test::WaveDisplacement wave;
  for (float height : {1e-3f, 0.05f, 50.0f}) {
    const ScreenMetric screen = ScreenMetric::lookAt(
        Vec3(0.7f, 0.4f, height), Vec3(2.0f, 1.5f, 0.0f), Vec3(0, 0, 1), 50.0f, 160, 90);
    const AdaptiveTessellation t = tessellateAdaptive(surface, screen, {}, {}, &wave);
    std::printf("  eye %g above: %d split, %zu micropolygons\n", height, t.stats.facesSplit,
                t.stats.micropolygons);
    EXPECT_TRUE(finitePositions(t.mesh)) << height;
    EXPECT_EQ(openInnerEdges(t.mesh, 2.0f), 0) << height;
  }
}

template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TEST(FaceSplit, SameBitsForOneAndTwoThreadsWithSplits) {
  const LimitSurface surface(test::refinedCube(3), SubdivisionScheme::CatmullClark);
  const test::WaveDisplacement wave;
  const ScreenMetric screen = ScreenMetric::lookAt(Vec3(0.4f, 0.3f, 1.9f), Vec3(1.0f, 0.8f, 0.0f),
                                                   Vec3(0, 1, 0), 40.0f, 320, 180);
  AdaptiveTessellation t[2];
  for (int threads : {1, 2}) {
    tbb::task_arena arena(threads);
    arena.execute([&] { t[threads - 1] = tessellateAdaptive(surface, screen, {}, {}, &wave); });
  }
  EXPECT_GT(t[0].stats.facesSplit, 0);
  EXPECT_TRUE(sameBits(t[0].edgeRates, t[1].edgeRates));
  EXPECT_TRUE(sameBits(t[0].mesh.positions, t[1].mesh.positions));
  EXPECT_TRUE(sameBits(t[0].mesh.indices, t[1].mesh.indices));
  EXPECT_TRUE(sameBits(t[0].mesh.triangleFace, t[1].mesh.triangleFace));
  EXPECT_TRUE(sameBits(t[0].mesh.cornerSt, t[1].mesh.cornerSt));
  ASSERT_EQ(t[0].grids.size(), t[1].grids.size());
  for (size_t g = 0; g < t[0].grids.size(); ++g) {
    EXPECT_EQ(t[0].grids[g].firstVertex, t[1].grids[g].firstVertex);
    EXPECT_EQ(t[0].grids[g].firstTriangle, t[1].grids[g].firstTriangle);
  }
}

// Triangles whose three corners all lie nearer the eye than `near` (or all farther than `far`).
struct DepthShare {
  size_t nearTriangles = 0, farTriangles = 0;
  float nearLegP99 = 0.0f;  // legs of the near triangles in view, in pixel footprints
};
DepthShare byDistance(const TessellatedMesh& m, const ScreenMetric& screen, float near, float far) {
  DepthShare out;
  std::vector<float> legs;
  for (size_t k = 0; k < m.numTriangles(); ++k) {
    Vec3 p[3];
    bool allNear = true, allFar = true, seen = true;
    for (int i = 0; i < 3; ++i) {
      p[i] = m.positions[m.indices[3 * k + i]];
      const float d = glm::length(p[i] - screen.eye);
      allNear = allNear && d < near;
      allFar = allFar && d > far;
      seen = seen && screen.pointInView(p[i]);
    }
    out.farTriangles += allFar;
    if (!allNear) continue;
    ++out.nearTriangles;
    if (!seen) continue;
    float e[3];
    for (int i = 0; i < 3; ++i) e[i] = screen.footprintLength(p[i], p[(i + 1) % 3]);
    std::sort(e, e + 3);
    legs.push_back(e[1]);
  }
  std::sort(legs.begin(), legs.end());
  if (!legs.empty()) out.nearLegP99 = legs[legs.size() * 99 / 100];
  return out;
}

// The hybrid raises relief only near the eye (FaceDicing::raiseDistance): a 4 x 4 ground seen
// from 3.5 to 7.5 units away, raised within 5 units of the eye only. Faces that reach beyond are
// split; the part beyond is coarse, the part near is diced as if the whole were raised, and there
// are no cracks between them.
TEST(FaceSplit, FacesAreDicedOnlyWhereTheyRaiseRelief) {
  const LimitSurface surface(test::grid(4), SubdivisionScheme::Bilinear);
  const ScreenMetric screen = ScreenMetric::lookAt(Vec3(2.0f, -3.0f, 1.5f), Vec3(2.0f, 2.0f, 0.0f),
                                                   Vec3(0, 0, 1), 50.0f, 160, 90);
  const test::WaveDisplacement wave;
  constexpr float kRaise = 5.0f;
  DicingSettings settings;
  settings.maxEdgeRate = 4096;
  const AdaptiveTessellation all = tessellateAdaptive(surface, screen, settings, {}, &wave);
  FaceDicing near;
  near.raiseDistance.assign(static_cast<size_t>(surface.numFaces()), kRaise);
  const AdaptiveTessellation part = tessellateAdaptive(surface, screen, settings, near, &wave);
  // Within kRaise less the cells' grow (the bound and half a cell), and beyond kRaise plus a face's
  // diagonal: every triangle there is in a part whose box is beyond.
  const float margin = wave.bound() + 0.5f * glm::length(Vec3(0.5f, 0.5f, 0.0f));
  const DepthShare a = byDistance(all.mesh, screen, kRaise - margin, kRaise + 1.5f);
  const DepthShare b = byDistance(part.mesh, screen, kRaise - margin, kRaise + 1.5f);
  std::printf(
      "  raised everywhere: %zu micropolygons (%zu near, legs p99 %.3f; %zu far)\n"
      "  raised within %g: %zu micropolygons (%zu near, legs p99 %.3f; %zu far), %d faces split\n",
      all.stats.micropolygons, a.nearTriangles, a.nearLegP99, a.farTriangles, kRaise,
      part.stats.micropolygons, b.nearTriangles, b.nearLegP99, b.farTriangles,
      part.stats.facesSplit);
  EXPECT_LT(part.stats.micropolygons, all.stats.micropolygons * 4 / 5);
  EXPECT_LT(b.farTriangles * 20, a.farTriangles);          // far parts: the coarse rate
  EXPECT_LE(b.nearLegP99, std::max(1.15f, a.nearLegP99));  // near parts: diced as before
  EXPECT_GT(b.nearTriangles, a.nearTriangles * 9 / 10);
  EXPECT_TRUE(finitePositions(part.mesh));
  EXPECT_EQ(openInnerEdges(part.mesh, 4.0f), 0);
  // A distance beyond the whole ground changes nothing; 0 raises nothing (no dicing anywhere).
  near.raiseDistance.assign(near.raiseDistance.size(), 1e3f);
  EXPECT_EQ(tessellateAdaptive(surface, screen, settings, near, &wave).stats.micropolygons,
            all.stats.micropolygons);
  near.raiseDistance.assign(near.raiseDistance.size(), 0.0f);
  EXPECT_LT(tessellateAdaptive(surface, screen, settings, near, &wave).stats.micropolygons,
            all.stats.micropolygons / 20);
  near.raiseDistance.assign(near.raiseDistance.size(), -1.0f);
  EXPECT_THROW(tessellateAdaptive(surface, screen, settings, near, &wave), Error);
}

// Under the micropolygon cap the split faces coarsen with their edges: the count fits.
TEST(FaceSplit, CapCountsTheSplitFaces) {
  const LimitSurface surface(test::grid(2), SubdivisionScheme::Bilinear);
  const ScreenMetric screen = ScreenMetric::lookAt(Vec3(1.0f, -0.2f, 0.4f), Vec3(1.0f, 2.0f, 0.0f),
                                                   Vec3(0, 0, 1), 40.0f, 160, 90);
  DicingSettings settings;
  settings.maxMicropolygons = 3000;
  const AdaptiveTessellation t = tessellateAdaptive(surface, screen, settings, {}, nullptr);
  std::printf("  capped: %zu micropolygons, %d faces split, coarsening %.3f\n",
              t.stats.micropolygons, t.stats.facesSplit, t.stats.coarsening);
  EXPECT_GT(t.stats.coarsening, 1.0f);
  EXPECT_LE(t.stats.micropolygons, settings.maxMicropolygons);
  EXPECT_GT(t.stats.micropolygons, settings.maxMicropolygons / 4);
  EXPECT_GT(t.stats.facesSplit, 0);
  EXPECT_EQ(openInnerEdges(t.mesh, 2.0f), 0);
}

}  // namespace
}  // namespace meso
