#include "meso/geometry/adaptive_tessellation.h"

#include "geometry/test_meshes.h"
#include "meso/core/error.h"
#include "meso/core/rng.h"
#include "meso/geometry/ray_scene.h"
#include "meso/scene/camera.h"
#include "meso/scene/choices.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <tuple>
#include <utility>
#include <vector>

namespace meso {
namespace {

// Height field h(x, y) = A sin(a x) sin(b y) over the plane z = 0 (normal +z), whose exact normal
// is normalize(-h_x, -h_y, 1).
struct HeightField : VertexDisplacement {
  float A = 0.15f, a = 2.0f, b = 3.0f;
  Vec3 offset(int, Vec2, const SurfacePoint& sp) const override {
    return A * std::sin(a * sp.P.x) * std::sin(b * sp.P.y) * sp.N;
  }
  float bound() const override { return A; }
  Vec3 normal(float x, float y) const {
    const float hx = A * a * std::cos(a * x) * std::sin(b * y);
    const float hy = A * b * std::sin(a * x) * std::cos(b * y);
    return glm::normalize(Vec3(-hx, -hy, 1.0f));
  }
};

// Quads whose edges got different rates (the case that needs Bfr's non-uniform patterns): equal
// rates R give 2 R^2 triangles.
int nonUniformQuads(const LimitSurface& surface, const TessellatedMesh& mesh) {
  std::vector<int> perFace(surface.numFaces(), 0);
  for (int f : mesh.triangleFace) ++perFace[f];
  int count = 0;
  for (int f = 0; f < surface.numFaces(); ++f) {
    if (surface.faceSize(f) != 4) continue;
    const int r = static_cast<int>(std::lround(std::sqrt(perFace[f] / 2.0)));
    count += perFace[f] != 2 * r * r;
  }
  return count;
}

void expectWatertight(const ControlMesh& control, const ScreenMetric& screen, int numRays,
                      DicingMetric metric) {
  const LimitSurface surface(control, SubdivisionScheme::CatmullClark);
  const test::WaveDisplacement wave;
  // Diced faces (at every other index) next to coarse ones, on top of the rates the distance gives.
  FaceDicing faces;
  for (int f = 0; f < surface.numFaces(); ++f) faces.needsDicing.push_back(f % 2 == 0);
  DicingSettings settings;
  settings.metric = metric;
  settings.coarseTolerance = 0.5f;  // coarse faces far coarser than the diced ones beside them
  const AdaptiveTessellation t = tessellateAdaptive(surface, screen, settings, faces, &wave);
  std::printf("  %s, %d faces: %zu micropolygons, edge rates %d..%d\n", choiceName(metric),
              surface.numFaces(), t.stats.micropolygons, t.stats.minEdgeRate, t.stats.maxEdgeRate);
  // The camera close to one side and coarse faces between diced ones make rates differ strongly,
  // also within single faces.
  EXPECT_GE(t.stats.maxEdgeRate, 8 * t.stats.minEdgeRate);
  EXPECT_GT(nonUniformQuads(surface, t.mesh), 0);
  EXPECT_EQ(test::countOpenEdges(t.mesh), 0);

  // Embree's WatertightTest, on the triangles alone and with the face interiors as Embree grids.
  RayScene triangles, grids;
  triangles.addMesh(t.mesh);
  grids.addMesh(t.mesh, t.grids);
  triangles.commit();
  grids.commit();
  Rng rng(1234);
  int escapes[2] = {0, 0};
  for (int i = 0; i < numRays; ++i) {
    const Vec3 origin =
        0.2f * Vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f);
    const Ray ray{origin, test::randomDirection(rng)};
    RayHit hit;
    escapes[0] += !triangles.intersect(ray, hit);
    escapes[1] += !grids.intersect(ray, hit);
  }
  EXPECT_EQ(escapes[0], 0) << "triangles";
  EXPECT_EQ(escapes[1], 0) << "grids";
}

TEST(AdaptiveTessellation, DisplacedClosedSurfacesWithMixedRatesAreWatertight) {
  // Eye 1.3 units in front of the +z side, looking at the object's centre.
  const ScreenMetric screen =
      ScreenMetric::lookAt(Vec3(0.3f, 0.2f, 2.3f), Vec3(0.0f), Vec3(0, 1, 0), 60.0f, 320, 180);
  for (DicingMetric metric : {DicingMetric::Isotropic, DicingMetric::Projected}) {
    expectWatertight(test::refinedCube(3), screen, 100000, metric);
    expectWatertight(test::mixedPrism(), screen, 100000, metric);
  }
}

// A large plane seen from just above it, looking at the horizon: the case the isotropic metric is
// for. Its micropolygons are at most about dicingRate pixel footprints long wherever they are in
// view; the projected metric leaves them many footprints long in depth.
struct GrazingDicing {
  std::vector<int> rates;
  size_t micropolygons = 0;
  size_t offScreen = 0;
  float worstLeg = 0.0f;  // longest micropolygon leg in view, in pixel footprints
  float legP99 = 0.0f;    // its 99th percentile
};

GrazingDicing diceGrazing(const LimitSurface& surface, const ScreenMetric& screen,
                          DicingMetric metric) {
  DicingSettings settings;
  settings.metric = metric;
  settings.maxEdgeRate = 4096;
  const AdaptiveTessellation t = tessellateAdaptive(surface, screen, settings, {}, nullptr);
  GrazingDicing out{t.edgeRates, t.stats.micropolygons, t.stats.offScreenMicropolygons, 0.0f, 0.0f};
  const test::InViewLegs legs = test::inViewLegs(t.mesh, screen);
  out.legP99 = legs.p99;
  out.worstLeg = legs.worst;
  return out;
}

TEST(AdaptiveTessellation, IsotropicMetricResolvesGrazingViews) {
  const LimitSurface surface(test::grid(24), SubdivisionScheme::Bilinear);
  const ScreenMetric screen = ScreenMetric::lookAt(
      Vec3(12.0f, -0.5f, 0.6f), Vec3(12.0f, 24.0f, 0.35f), Vec3(0, 0, 1), 40.0f, 160, 90);
  const GrazingDicing iso = diceGrazing(surface, screen, DicingMetric::Isotropic);
  const GrazingDicing proj = diceGrazing(surface, screen, DicingMetric::Projected);
  std::printf(
      "  isotropic: %zu micropolygons, legs in view p99 %.3f, max %.3f footprints\n"
      "  projected: %zu micropolygons, legs in view p99 %.3f, max %.3f footprints\n",
      iso.micropolygons, iso.legP99, iso.worstLeg, proj.micropolygons, proj.legP99, proj.worstLeg);
  ASSERT_EQ(iso.rates.size(), proj.rates.size());
  long isoSum = 0, projSum = 0;
  for (size_t e = 0; e < iso.rates.size(); ++e) {
    EXPECT_GE(iso.rates[e], proj.rates[e]) << "edge " << e;
    isoSum += iso.rates[e];
    projSum += proj.rates[e];
  }
  EXPECT_GT(isoSum, projSum * 3 / 2);  // grazing: the projected metric is far coarser
  EXPECT_GT(iso.micropolygons, 2 * proj.micropolygons);
  // Dicing rate 1: the metric's bound, with 10% for the edges' five sample points; the longest
  // legs sit where Bfr joins rates that differ along face borders.
  EXPECT_LE(iso.legP99, 1.1f);
  EXPECT_LE(iso.worstLeg, 1.5f);
  EXPECT_GT(proj.legP99, 3.0f);  // what the isotropic metric fixes
  // The plane reaches far beyond the view on both sides: some micropolygons are off screen, most
  // (by far the smallest ones, near the eye) in view.
  EXPECT_GT(iso.offScreen, 0u);
  EXPECT_LT(iso.offScreen, iso.micropolygons / 2);
}

// The mean extents along x and along y of the triangles whose centroids lie in [x0, x1] x [y0, y1].
Vec2 meanExtents(const TessellatedMesh& mesh, float x0, float x1, float y0, float y1) {
  Vec2 sum(0.0f);
  int n = 0;
  for (size_t t = 0; t < mesh.numTriangles(); ++t) {
    Vec3 lo(1e30f), hi(-1e30f);
    for (int k = 0; k < 3; ++k) {
      lo = glm::min(lo, mesh.positions[mesh.indices[3 * t + k]]);
      hi = glm::max(hi, mesh.positions[mesh.indices[3 * t + k]]);
    }
    const Vec3 c = 0.5f * (lo + hi);
    if (c.x < x0 || c.x > x1 || c.y < y0 || c.y > y1) continue;
    sum += Vec2(hi.x - lo.x, hi.y - lo.y);
    ++n;
  }
  return n > 0 ? sum / static_cast<float>(n) : Vec2(0.0f);
}

// DicingSettings::acrossViewCap: where the texel cap binds (near the eye), a grazing view keeps the
// whole cap along the view (y) and about half of it across (x); a view from straight above keeps
// nearly the whole cap both ways (sin^2(theta_V) weighs the change), and the rates never exceed
// the isotropic ones. The face interiors follow their edges (Bfr's inner rates).
TEST(AdaptiveTessellation, AcrossViewCapHalvesTheCapAcrossAGrazingViewOnly) {
  const LimitSurface surface(test::grid(24), SubdivisionScheme::Bilinear);
  FaceDicing capped;
  capped.texelCap.assign(surface.numFaces(), 16);
  DicingSettings iso;
  iso.splitFaces = false;
  DicingSettings aniso = iso;
  aniso.acrossViewCap = 0.5f;
  const ScreenMetric grazing = ScreenMetric::lookAt(
      Vec3(12.0f, -0.5f, 0.6f), Vec3(12.0f, 24.0f, 0.35f), Vec3(0, 0, 1), 40.0f, 160, 90);
  const AdaptiveTessellation a = tessellateAdaptive(surface, grazing, iso, capped, nullptr);
  const AdaptiveTessellation b = tessellateAdaptive(surface, grazing, aniso, capped, nullptr);
  ASSERT_EQ(a.edgeRates.size(), b.edgeRates.size());
  for (size_t e = 0; e < a.edgeRates.size(); ++e) EXPECT_LE(b.edgeRates[e], a.edgeRates[e]);
  // In front of the eye, 2.5 to 4.5 units ahead: the cap binds (cells 1/16 a side in both).
  const Vec2 ea = meanExtents(a.mesh, 11.0f, 13.0f, 2.5f, 4.5f);
  const Vec2 eb = meanExtents(b.mesh, 11.0f, 13.0f, 2.5f, 4.5f);
  EXPECT_NEAR(ea.x, 1.0f / 16.0f, 0.01f);
  EXPECT_NEAR(ea.y, 1.0f / 16.0f, 0.01f);
  EXPECT_NEAR(eb.y, 1.0f / 16.0f, 0.01f);  // along the view: the whole cap
  EXPECT_GT(eb.x, 1.6f * eb.y);            // across: about half of it (9 of 16 here)
  EXPECT_LT(eb.x, 2.1f * eb.y);
  EXPECT_LT(b.stats.micropolygons, a.stats.micropolygons);

  // From 10 units straight above the middle the cap binds everywhere in view, and theta_V stays
  // within 37 degrees (the view's corners): edges keep at least 1 - 0.5 sin^2(37 deg) = 0.82 of
  // the cap, 14 of 16.
  const ScreenMetric above = ScreenMetric::lookAt(
      Vec3(12.0f, 12.0f, 10.0f), Vec3(12.0f, 12.0f, 0.0f), Vec3(0, 1, 0), 40.0f, 640, 360);
  const AdaptiveTessellation c = tessellateAdaptive(surface, above, iso, capped, nullptr);
  const AdaptiveTessellation d = tessellateAdaptive(surface, above, aniso, capped, nullptr);
  EXPECT_EQ(c.stats.maxEdgeRate, 16);
  for (size_t e = 0; e < c.edgeRates.size(); ++e) {
    EXPECT_LE(d.edgeRates[e], c.edgeRates[e]);
    EXPECT_GE(d.edgeRates[e], std::min(c.edgeRates[e], 14)) << "edge " << e;
  }
}

// Facet normals of the displaced plane approach the exact normal of the height field as
// micropolygons shrink (Chan 2002: facets only converge; shading uses the limit frames instead).
float meanFacetAngle(const TessellatedMesh& mesh, const HeightField& field) {
  double sum = 0.0;
  for (size_t t = 0; t < mesh.numTriangles(); ++t) {
    const Vec3 a = mesh.positions[mesh.indices[3 * t]], b = mesh.positions[mesh.indices[3 * t + 1]],
               c = mesh.positions[mesh.indices[3 * t + 2]];
    const Vec3 centroid = (a + b + c) / 3.0f;
    const Vec3 facet = glm::normalize(glm::cross(b - a, c - a));
    const float cosine = glm::dot(facet, field.normal(centroid.x, centroid.y));
    sum += std::acos(std::clamp(cosine, -1.0f, 1.0f));
  }
  return static_cast<float>(sum / static_cast<double>(std::max<size_t>(mesh.numTriangles(), 1)));
}

TEST(AdaptiveTessellation, FacetNormalsConvergeToTheDisplacedSurfaceNormal) {
  const LimitSurface surface(test::grid(4), SubdivisionScheme::CatmullClark);
  const HeightField field;
  const ScreenMetric screen = ScreenMetric::lookAt(Vec3(2.0f, 2.0f, 4.0f), Vec3(2.0f, 2.0f, 0.0f),
                                                   Vec3(0, 1, 0), 60.0f, 160, 90);
  float previous = kPi;
  for (float dicingRate : {4.0f, 1.0f, 0.25f}) {
    DicingSettings settings;
    settings.dicingRate = dicingRate;
    const AdaptiveTessellation t = tessellateAdaptive(surface, screen, settings, {}, &field);
    EXPECT_EQ(t.stats.offScreenMicropolygons, 0u);  // the whole grid is in view
    const float angle = meanFacetAngle(t.mesh, field);
    std::printf("  dicing rate %.2f px: %zu micropolygons, mean facet angle %.4f degrees\n",
                dicingRate, t.stats.micropolygons, degrees(angle));
    EXPECT_LT(angle, 0.5f * previous) << "dicing rate " << dicingRate;
    previous = angle;
  }
}

TEST(AdaptiveTessellation, DisplacementStaysWithinItsBound) {
  const LimitSurface surface(test::refinedCube(2), SubdivisionScheme::CatmullClark);
  const test::WaveDisplacement wave;
  const ScreenMetric screen =
      ScreenMetric::lookAt(Vec3(1.0f, 2.0f, 4.0f), Vec3(0.0f), Vec3(0, 1, 0), 40.0f, 320, 180);
  const AdaptiveTessellation t = tessellateAdaptive(surface, screen, {}, {}, &wave);
  // Each corner's own face and st lead back to the limit point the vertex was displaced from
  // (shared vertices were displaced once, from their first face: the same limit point).
  float largest = 0.0f;
  for (size_t c = 0; c < t.mesh.indices.size(); ++c) {
    const Vec3 limit = surface.evaluate(t.mesh.triangleFace[c / 3], t.mesh.cornerSt[c]).P;
    const float d = glm::length(t.mesh.positions[t.mesh.indices[c]] - limit);
    ASSERT_LE(d, wave.bound() * (1.0f + 1e-5f) + 1e-5f) << "corner " << c;
    largest = std::max(largest, d);
  }
  EXPECT_GT(largest, 0.5f * wave.bound());  // the relief is really there
}

size_t micropolygons(const LimitSurface& surface, float distance, const FaceDicing& faces) {
  const Vec3 eye = distance * glm::normalize(Vec3(0.4f, 0.5f, 1.0f));
  const ScreenMetric screen = ScreenMetric::lookAt(eye, Vec3(0.0f), Vec3(0, 1, 0), 40.0f, 640, 360);
  return tessellateAdaptive(surface, screen, {}, faces, nullptr).stats.micropolygons;
}

TEST(AdaptiveTessellation, MicropolygonsFallWithTheSquareOfDistance) {
  const LimitSurface surface(test::refinedCube(2), SubdivisionScheme::CatmullClark);
  const size_t near = micropolygons(surface, 6.0f, {}), far = micropolygons(surface, 12.0f, {});
  const double ratio = static_cast<double>(far) / static_cast<double>(near);
  std::printf("  distance 6: %zu, distance 12: %zu micropolygons (ratio %.3f)\n", near, far, ratio);
  EXPECT_GE(ratio, 0.2);
  EXPECT_LE(ratio, 0.33);
}

TEST(AdaptiveTessellation, DistantCameraGivesTheCoarseTessellationOnly) {
  const LimitSurface surface(test::refinedCube(2), SubdivisionScheme::CatmullClark);
  FaceDicing none;
  none.needsDicing.assign(surface.numFaces(), 0);
  // At 6 units dicing adds triangles; at 5000 it has nothing left to add.
  EXPECT_GT(micropolygons(surface, 6.0f, {}), micropolygons(surface, 6.0f, none));
  EXPECT_EQ(micropolygons(surface, 5000.0f, {}), micropolygons(surface, 5000.0f, none));
}

// Camera rays on an n x n grid in every pixel of `camera` that hit the mesh.
size_t coveredSubpixels(const TessellatedMesh& mesh, const Camera& camera, int width, int height,
                        int n) {
  RayScene scene;
  scene.addMesh(mesh);
  scene.commit();
  size_t hits = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          RayHit hit;
          hits += scene.intersect(camera.generateRay(x + (i + 0.5f) / static_cast<float>(n),
                                                     y + (j + 0.5f) / static_cast<float>(n)),
                                  hit);
        }
  return hits;
}

// Where nothing is diced (a far object that the hybrid draws with its tables), the coarse rate
// follows the limit surface: chords cut inside a convex silhouette and shrink what the object
// covers, which darkens its mean intensity. At a 0.5 px tolerance this cube covered 3.4% less than
// a fine uniform tessellation; the default tolerance keeps it under 0.1%.
TEST(AdaptiveTessellation, CoarseSilhouettesCoverWhatTheLimitSurfaceCovers) {
  const LimitSurface surface(test::cube(), SubdivisionScheme::CatmullClark);
  CameraSettings view;
  view.position = Vec3(1.2f, 1.6f, 3.2f);
  view.width = 160;
  view.height = 90;
  const Camera camera(view);
  FaceDicing none;
  none.needsDicing.assign(static_cast<size_t>(surface.numFaces()), 0);
  const size_t limit =
      coveredSubpixels(tessellateUniform(surface, 32), camera, view.width, view.height, 4);
  const auto coverage = [&](float tolerance) {
    DicingSettings settings;
    if (tolerance > 0.0f) settings.coarseTolerance = tolerance;
    const AdaptiveTessellation t =
        tessellateAdaptive(surface, camera.screen(), settings, none, nullptr);
    const double c =
        static_cast<double>(coveredSubpixels(t.mesh, camera, view.width, view.height, 4)) /
        static_cast<double>(limit);
    std::printf("  tolerance %.3g px: %zu triangles, coverage %.5f of the limit surface's\n",
                tolerance > 0.0f ? tolerance : settings.coarseTolerance, t.stats.micropolygons, c);
    return c;
  };
  std::printf("  limit surface (uniform rate 32): %.0f pixels\n", limit / 16.0);
  ASSERT_GT(limit, 16u * 1500u);  // the object is tens of pixels across
  const double loose = coverage(0.5f), byDefault = coverage(0.0f);
  EXPECT_LT(loose, 0.995);  // the test can see the shrinkage
  EXPECT_GT(byDefault, 0.999);
  EXPECT_LE(byDefault, 1.0002);
}

TEST(AdaptiveTessellation, CapCoarsensWithAWarning) {
  const LimitSurface surface(test::refinedCube(2), SubdivisionScheme::CatmullClark);
  const ScreenMetric screen =
      ScreenMetric::lookAt(Vec3(0.0f, 1.0f, 5.0f), Vec3(0.0f), Vec3(0, 1, 0), 40.0f, 640, 360);
  const AdaptiveTessellation full = tessellateAdaptive(surface, screen, {}, {}, nullptr);
  EXPECT_TRUE(full.warning.empty()) << full.warning;
  EXPECT_EQ(full.stats.coarsening, 1.0f);
  DicingSettings settings;
  settings.maxMicropolygons = 5000;
  const AdaptiveTessellation capped = tessellateAdaptive(surface, screen, settings, {}, nullptr);
  std::printf(
      "  uncapped %zu, capped %zu micropolygons (cap %zu): as asked nearer than %.3g, "
      "up to %.3gx\n  %s\n",
      full.stats.micropolygons, capped.stats.micropolygons, settings.maxMicropolygons,
      capped.stats.coarsenedBeyond, capped.stats.coarsening, capped.warning.c_str());
  ASSERT_GT(full.stats.micropolygons, 10 * settings.maxMicropolygons);
  EXPECT_LE(capped.stats.micropolygons, settings.maxMicropolygons);
  EXPECT_GT(capped.stats.micropolygons, settings.maxMicropolygons / 4);  // coarsened, not wiped out
  EXPECT_FALSE(capped.warning.empty());
  EXPECT_GT(capped.stats.coarsening, 1.0f);
}

// A w x l strip of unit quads in z = 0 (x in [-w/2, w/2], y in [0, l]), facing +z: a ground.
ControlMesh strip(int w, int l) {
  ControlMesh mesh;
  for (int j = 0; j <= l; ++j)
    for (int i = 0; i <= w; ++i) mesh.positions.emplace_back(i - 0.5f * w, j, 0.0f);
  for (int j = 0; j < l; ++j)
    for (int i = 0; i < w; ++i) {
      const int a = j * (w + 1) + i;
      test::addFace(mesh, {a, a + 1, a + w + 2, a + w + 1});
    }
  return mesh;
}

std::vector<int> trianglesPerFace(const LimitSurface& surface, const TessellatedMesh& mesh) {
  std::vector<int> perFace(surface.numFaces(), 0);
  for (int f : mesh.triangleFace) ++perFace[f];
  return perFace;
}

// The triangles whose corners all lie nearer than `distance` to `eye`, each as its corners'
// coordinates (corners sorted), sorted: equal when that part of two meshes is the same, bit for
// bit.
std::vector<std::array<float, 9>> trianglesNearerThan(const TessellatedMesh& mesh, Vec3 eye,
                                                      float distance) {
  std::vector<std::array<float, 9>> near;
  for (size_t t = 0; t < mesh.numTriangles(); ++t) {
    std::array<std::array<float, 3>, 3> corners;
    bool inside = true;
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = mesh.positions[mesh.indices[3 * t + k]];
      inside = inside && glm::length(p - eye) < distance;
      corners[k] = {p.x, p.y, p.z};
    }
    if (!inside) continue;
    std::sort(corners.begin(), corners.end());
    near.push_back({corners[0][0], corners[0][1], corners[0][2], corners[1][0], corners[1][1],
                    corners[1][2], corners[2][0], corners[2][1], corners[2][2]});
  }
  std::sort(near.begin(), near.end());
  return near;
}

// A 4 x 128 ground seen from 0.6 above, 1.5 before its near end, looking along it, under a cap of
// 2/3 of what it asks: its micropolygons nearer than where the cap began (beyond 2 units) are
// those asked, bit for bit, faces 32 units away are coarsened, and the count fits. Coarsening every
// rate by one factor until it fits (the control, by the dicing rate) changes them, so this test
// fails for a uniform cap.
TEST(AdaptiveTessellation, CapCoarsensTheFarthestGeometryFirst) {
  const LimitSurface surface(strip(4, 128), SubdivisionScheme::Bilinear);
  const ScreenMetric screen = ScreenMetric::lookAt(Vec3(0.0f, -1.5f, 0.6f), Vec3(0.0f, 10.0f, 0.0f),
                                                   Vec3(0, 0, 1), 40.0f, 160, 90);
  DicingSettings settings;
  settings.maxEdgeRate = 4096;  // no rate clamped
  const AdaptiveTessellation full = tessellateAdaptive(surface, screen, settings, {}, nullptr);
  settings.maxMicropolygons = full.stats.micropolygons * 2 / 3;
  const AdaptiveTessellation capped = tessellateAdaptive(surface, screen, settings, {}, nullptr);
  std::printf(
      "  uncapped %zu, capped %zu micropolygons (cap %zu): as asked nearer than %.3g, "
      "up to %.3gx\n  %s\n",
      full.stats.micropolygons, capped.stats.micropolygons, settings.maxMicropolygons,
      capped.stats.coarsenedBeyond, capped.stats.coarsening, capped.warning.c_str());
  EXPECT_LE(capped.stats.micropolygons, settings.maxMicropolygons);
  EXPECT_GT(capped.stats.micropolygons, settings.maxMicropolygons * 9 / 10);
  EXPECT_GT(capped.stats.coarsenedBeyond, 2.0f);
  EXPECT_NE(capped.warning.find("as asked nearer than"), std::string::npos) << capped.warning;
  const float near = capped.stats.coarsenedBeyond;
  const auto askedNear = trianglesNearerThan(full.mesh, screen.eye, near);
  EXPECT_GT(askedNear.size(), 10000u);
  EXPECT_TRUE(trianglesNearerThan(capped.mesh, screen.eye, near) == askedNear);
  const std::vector<int> asked = trianglesPerFace(surface, full.mesh);
  const std::vector<int> got = trianglesPerFace(surface, capped.mesh);
  EXPECT_LT(got[4 * 32], asked[4 * 32]);  // farther away, coarsened

  // The control: one factor on every rate, raised until the count fits.
  float factor = 1.0f;
  AdaptiveTessellation uniform;
  do {
    factor *= 1.05f;
    DicingSettings coarser = settings;
    coarser.maxMicropolygons = 80'000'000;
    coarser.dicingRate = factor;
    uniform = tessellateAdaptive(surface, screen, coarser, {}, nullptr);
  } while (uniform.stats.micropolygons > settings.maxMicropolygons);
  const auto evenNear = trianglesNearerThan(uniform.mesh, screen.eye, near);
  std::printf("  %zu micropolygons nearer than %.3g; coarsened uniformly by %.3g, %zu\n",
              askedNear.size(), near, factor, evenNear.size());
  EXPECT_LT(evenNear.size(), askedNear.size());
}

// Two surfaces of one frame under one cap, the far one first: the cap coarsens the far one and
// leaves the near one as asked (a cap spent surface by surface would give the first all it asks).
TEST(AdaptiveTessellation, OneCapForSeveralSurfacesCoarsensTheFarthestFirst) {
  ControlMesh farMesh = strip(4, 16);
  for (Vec3& p : farMesh.positions) p.y += 40.0f;
  const LimitSurface farGround(farMesh, SubdivisionScheme::Bilinear);
  const LimitSurface nearGround(strip(4, 4), SubdivisionScheme::Bilinear);
  const ScreenMetric screen = ScreenMetric::lookAt(Vec3(0.0f, -1.5f, 0.6f), Vec3(0.0f, 10.0f, 0.0f),
                                                   Vec3(0, 0, 1), 40.0f, 160, 90);
  const test::WaveDisplacement wave;
  DicingSettings settings;
  const AdaptiveSurface surfaces[2] = {
      {.surface = &farGround, .faces = {}, .displacement = &wave},
      {.surface = &nearGround, .faces = {}, .displacement = &wave}};
  const std::vector<AdaptiveTessellation> full = tessellateAdaptive(surfaces, screen, settings);
  const size_t asked = full[0].stats.micropolygons + full[1].stats.micropolygons;
  settings.maxMicropolygons = full[1].stats.micropolygons + full[0].stats.micropolygons / 4;
  const std::vector<AdaptiveTessellation> capped = tessellateAdaptive(surfaces, screen, settings);
  std::printf("  asked %zu (far %zu, near %zu), cap %zu: far %zu, near %zu\n  %s\n", asked,
              full[0].stats.micropolygons, full[1].stats.micropolygons, settings.maxMicropolygons,
              capped[0].stats.micropolygons, capped[1].stats.micropolygons,
              capped[0].warning.c_str());
  EXPECT_LE(capped[0].stats.micropolygons + capped[1].stats.micropolygons,
            settings.maxMicropolygons);
  EXPECT_EQ(capped[1].stats.micropolygons, full[1].stats.micropolygons);
  EXPECT_TRUE(capped[1].edgeRates == full[1].edgeRates);
  EXPECT_LT(capped[0].stats.micropolygons, full[0].stats.micropolygons / 3);
  EXPECT_EQ(capped[0].stats.coarsenedBeyond, capped[1].stats.coarsenedBeyond);
  EXPECT_GT(capped[0].stats.coarsening, 1.0f);
  EXPECT_EQ(capped[1].stats.coarsening, 1.0f);  // wholly nearer than D
  EXPECT_FALSE(capped[0].warning.empty());
  // The one-surface form is the same as a span of one.
  const AdaptiveTessellation one = tessellateAdaptive(nearGround, screen, settings, {}, &wave);
  EXPECT_TRUE(one.edgeRates == full[1].edgeRates);
}

template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TEST(AdaptiveTessellation, SameBitsForOneAndTwoThreads) {
  const LimitSurface surface(test::mixedPrism(), SubdivisionScheme::CatmullClark);
  const test::WaveDisplacement wave;
  const ScreenMetric screen =
      ScreenMetric::lookAt(Vec3(0.5f, 1.0f, 3.0f), Vec3(0.0f), Vec3(0, 1, 0), 50.0f, 320, 180);
  FaceDicing faces;
  faces.needsDicing = {1, 0, 1, 1, 0, 1, 1, 0};
  faces.texelCap = {0, 0, 12, 0, 0, 40, 0, 0};
  // As asked, and under a cap that coarsens the far faces.
  for (size_t cap : {size_t{80'000'000}, size_t{3000}}) {
    DicingSettings settings;
    settings.maxMicropolygons = cap;
    AdaptiveTessellation t[2];
    for (int threads : {1, 2}) {
      tbb::task_arena arena(threads);
      arena.execute(
          [&] { t[threads - 1] = tessellateAdaptive(surface, screen, settings, faces, &wave); });
    }
    EXPECT_GT(t[0].stats.micropolygons, 1000u);
    EXPECT_EQ(t[0].stats.coarsening > 1.0f, cap == 3000);
    EXPECT_EQ(t[0].stats.coarsenedBeyond, t[1].stats.coarsenedBeyond);
    EXPECT_TRUE(sameBits(t[0].edgeRates, t[1].edgeRates));
    EXPECT_TRUE(sameBits(t[0].mesh.positions, t[1].mesh.positions));
    EXPECT_TRUE(sameBits(t[0].mesh.indices, t[1].mesh.indices));
    EXPECT_TRUE(sameBits(t[0].mesh.triangleFace, t[1].mesh.triangleFace));
    EXPECT_TRUE(sameBits(t[0].mesh.cornerSt, t[1].mesh.cornerSt));
  }
}

// Equal rates everywhere are the uniform tessellation, bit for bit.
TEST(AdaptiveTessellation, FarCameraWithoutViewMatchesUniformRateOne) {
  const LimitSurface surface(test::mixedPrism(), SubdivisionScheme::CatmullClark);
  // Looking away: every face is culled, so every edge gets rate 1.
  const ScreenMetric screen = ScreenMetric::lookAt(Vec3(0.0f, 0.0f, 5.0f), Vec3(0.0f, 0.0f, 10.0f),
                                                   Vec3(0, 1, 0), 40.0f, 640, 360);
  const AdaptiveTessellation t = tessellateAdaptive(surface, screen, {}, {}, nullptr);
  EXPECT_EQ(t.stats.facesCulled, surface.numFaces());
  EXPECT_EQ(t.stats.offScreenMicropolygons, t.stats.micropolygons);
  const TessellatedMesh u = tessellateUniform(surface, 1);
  // The same triangles a face, the same corners and st; quads are whole grids here (their corners
  // copied into a block of four points, their diagonal the grid's), so compare per face.
  ASSERT_EQ(t.mesh.numTriangles(), u.numTriangles());
  using Corner = std::tuple<float, float, float, float, float>;
  const auto corners = [](const TessellatedMesh& m) {
    std::map<int, std::vector<Corner>> out;
    for (size_t k = 0; k < m.numTriangles(); ++k)
      for (int j = 0; j < 3; ++j) {
        const Vec3 p = m.positions[m.indices[3 * k + j]];
        const Vec2 st = m.cornerSt[3 * k + j];
        out[m.triangleFace[k]].emplace_back(p.x, p.y, p.z, st.x, st.y);
      }
    for (auto& [face, list] : out) {
      std::sort(list.begin(), list.end());
      list.erase(std::unique(list.begin(), list.end()), list.end());
    }
    return out;
  };
  EXPECT_EQ(corners(t.mesh), corners(u));
  size_t wholeGrids = 0;
  for (const TriangleGrid& g : t.grids) wholeGrids += g.width == 2 && g.height == 2;
  EXPECT_GT(wholeGrids, 0u);
}

// Quads of one rate on every edge are whole Embree grids, border included: with gridsOnly no
// triangle of theirs is stored, and each grid's border points are copies, bit for bit, of the
// points the neighbours share (so rays cannot leak between grids).
TEST(AdaptiveTessellation, UniformQuadsAreWholeGrids) {
  const LimitSurface surface(test::grid(4), SubdivisionScheme::Bilinear);
  const ScreenMetric screen = ScreenMetric::lookAt(Vec3(2.0f, 2.0f, 40.0f), Vec3(2.0f, 2.0f, 0.0f),
                                                   Vec3(0, 1, 0), 30.0f, 160, 90);
  FaceDicing faces;
  faces.texelCap.assign(surface.numFaces(), 6);
  faces.texelFloor.assign(surface.numFaces(), 6);  // every edge at rate 6
  DicingSettings settings;
  settings.gridsOnly = true;
  const test::WaveDisplacement wave;
  const AdaptiveTessellation t = tessellateAdaptive(surface, screen, settings, faces, &wave);
  EXPECT_EQ(t.stats.minEdgeRate, 6);
  EXPECT_EQ(t.stats.maxEdgeRate, 6);
  EXPECT_EQ(t.mesh.numTriangles(), 0u);
  EXPECT_EQ(t.mesh.gridOnlyTriangles, 16u * 72u);
  ASSERT_EQ(t.grids.size(), 16u);
  // The shared points: the 5 x 5 vertices and 5 points on each of 40 edges, outside the blocks.
  std::vector<char> inBlock(t.mesh.positions.size(), 0);
  for (const TriangleGrid& g : t.grids) std::fill_n(inBlock.begin() + g.firstVertex, 49, 1);
  std::vector<Vec3> shared;
  for (size_t i = 0; i < inBlock.size(); ++i)
    if (!inBlock[i]) shared.push_back(t.mesh.positions[i]);
  EXPECT_EQ(shared.size(), 25u + 40u * 5u);
  EXPECT_EQ(t.mesh.positions.size(), shared.size() + 16u * 49u);
  for (const TriangleGrid& g : t.grids) {
    EXPECT_EQ(g.width, 7);
    EXPECT_EQ(g.height, 7);
    EXPECT_EQ(g.firstTriangle, TriangleGrid::kNotInMesh);
    for (int j = 0; j < 7; ++j)
      for (int i = 0; i < 7; ++i) {
        if (i > 0 && i < 6 && j > 0 && j < 6) continue;  // interior: the grid's own points
        const Vec3 p = t.mesh.positions[g.firstVertex + size_t(j) * 7 + size_t(i)];
        const auto same = [&](const Vec3& q) { return std::memcmp(&p, &q, sizeof(Vec3)) == 0; };
        EXPECT_TRUE(std::any_of(shared.begin(), shared.end(), same))
            << "grid of face " << g.face << ", point (" << i << ", " << j << ")";
      }
  }
}

TEST(AdaptiveTessellation, TexelCapAndMaxEdgeRateBoundTheRates) {
  const LimitSurface surface(test::refinedCube(2), SubdivisionScheme::CatmullClark);
  const ScreenMetric screen =
      ScreenMetric::lookAt(Vec3(0.0f, 0.0f, 2.5f), Vec3(0.0f), Vec3(0, 1, 0), 60.0f, 640, 360);
  DicingSettings settings;
  settings.maxEdgeRate = 64;
  settings.coarseTolerance = 0.5f;  // a coarse rate below the cap, so that the cap shows
  const AdaptiveTessellation free = tessellateAdaptive(surface, screen, settings, {}, nullptr);
  EXPECT_EQ(free.stats.maxEdgeRate, 64);
  FaceDicing capped;
  capped.texelCap.assign(surface.numFaces(), 10);
  const AdaptiveTessellation t = tessellateAdaptive(surface, screen, settings, capped, nullptr);
  // The cap bounds dicing; only the coarse rate (following the limit surface) may exceed it.
  EXPECT_LE(t.stats.maxEdgeRate, 10 + 4);
  EXPECT_LT(t.stats.micropolygons, free.stats.micropolygons);
}

// A texel floor raises the rate of every diced edge in view to it (never above the cap), and
// leaves faces out of view alone.
TEST(AdaptiveTessellation, TexelFloorRaisesDicedEdgesUpToTheCap) {
  const LimitSurface surface(test::refinedCube(2), SubdivisionScheme::CatmullClark);
  // Far away, so pixel dicing asks for rate 1 or 2 only.
  const ScreenMetric screen =
      ScreenMetric::lookAt(Vec3(0.0f, 0.0f, 60.0f), Vec3(0.0f), Vec3(0, 1, 0), 30.0f, 160, 90);
  DicingSettings settings;
  settings.coarseTolerance = 0.5f;  // and so does following the limit surface
  const AdaptiveTessellation free = tessellateAdaptive(surface, screen, settings, {}, nullptr);
  EXPECT_LE(free.stats.maxEdgeRate, 4);
  FaceDicing floored;
  floored.texelFloor.assign(surface.numFaces(), 12);
  const AdaptiveTessellation t = tessellateAdaptive(surface, screen, settings, floored, nullptr);
  EXPECT_EQ(t.stats.minEdgeRate, 12);
  EXPECT_EQ(t.stats.maxEdgeRate, 12);
  floored.texelCap.assign(surface.numFaces(), 7);
  const AdaptiveTessellation capped =
      tessellateAdaptive(surface, screen, settings, floored, nullptr);
  EXPECT_EQ(capped.stats.maxEdgeRate, 7);
  // Looking away: every face is culled and the floor does not apply.
  const ScreenMetric away = ScreenMetric::lookAt(Vec3(0.0f, 0.0f, 60.0f), Vec3(0.0f, 0.0f, 90.0f),
                                                 Vec3(0, 1, 0), 30.0f, 160, 90);
  EXPECT_EQ(tessellateAdaptive(surface, away, {}, floored, nullptr).stats.maxEdgeRate, 1);
  FaceDicing negative;
  negative.texelFloor.assign(surface.numFaces(), -1);
  EXPECT_THROW(tessellateAdaptive(surface, screen, {}, negative, nullptr), Error);
}

TEST(AdaptiveTessellation, InvalidSettingsThrow) {
  const LimitSurface surface(test::cube(), SubdivisionScheme::CatmullClark);
  const ScreenMetric screen;
  DicingSettings bad;
  bad.dicingRate = 0.0f;
  EXPECT_THROW(tessellateAdaptive(surface, screen, bad, {}, nullptr), Error);
  bad = DicingSettings{};
  bad.maxEdgeRate = 0;
  EXPECT_THROW(tessellateAdaptive(surface, screen, bad, {}, nullptr), Error);
  FaceDicing wrongSize;
  wrongSize.needsDicing.assign(3, 1);
  EXPECT_THROW(tessellateAdaptive(surface, screen, {}, wrongSize, nullptr), Error);
}

// Grids change how Embree stores the mesh, not what a hit reports: the same triangle (but for rays
// through a shared edge), distance and patch coordinates as the all-triangle scene.
TEST(AdaptiveTessellation, GridScenesReportTheSameHitsAsTriangleScenes) {
  const LimitSurface surface(test::refinedCube(2), SubdivisionScheme::CatmullClark);
  const test::WaveDisplacement wave;
  const ScreenMetric screen =
      ScreenMetric::lookAt(Vec3(1.0f, 1.5f, 4.0f), Vec3(0.0f), Vec3(0, 1, 0), 40.0f, 320, 180);
  const AdaptiveTessellation t = tessellateAdaptive(surface, screen, {}, {}, &wave);
  size_t inGrids = 0;
  for (const TriangleGrid& g : t.grids) inGrids += 2 * size_t(g.width - 1) * (g.height - 1);
  std::printf("  %zu of %zu micropolygons in %zu grids\n", inGrids, t.mesh.numTriangles(),
              t.grids.size());
  EXPECT_GT(inGrids, t.mesh.numTriangles() / 2);
  RayScene triangles, grids;
  triangles.addMesh(t.mesh);
  EXPECT_EQ(grids.addMesh(t.mesh, t.grids), 0);
  triangles.commit();
  grids.commit();
  EXPECT_EQ(grids.numTriangles(), t.mesh.numTriangles());
  // The triangles outside the grids (the stitching between rates) come two to a cell where they
  // share an edge: most do.
  const size_t outside = t.mesh.numTriangles() - inGrids;
  const size_t cells = grids.numPrimitives() - t.grids.size();
  std::printf("  %zu triangles outside the grids in %zu cells\n", outside, cells);
  EXPECT_GE(2 * cells, outside);
  EXPECT_LT(cells, outside * 6 / 10);
  Rng rng(99);
  int sameTriangle = 0, hits = 0, gridKnows = 0;
  for (int i = 0; i < 20000; ++i) {
    const Ray ray{Vec3(0.0f), test::randomDirection(rng)};
    RayHit a, b;
    ASSERT_TRUE(triangles.intersect(ray, a));
    ASSERT_TRUE(grids.intersect(ray, b));
    ++hits;
    sameTriangle += a.triangle == b.triangle;
    EXPECT_EQ(b.mesh, 0);
    EXPECT_NEAR(a.t, b.t, 1e-5f * a.t);
    const Vec2 stA = t.mesh.patchCoords(a.triangle, a.b1, a.b2);
    const Vec2 stB = t.mesh.patchCoords(b.triangle, b.b1, b.b2);
    if (t.mesh.triangleFace[a.triangle] == t.mesh.triangleFace[b.triangle]) {
      EXPECT_LT(glm::length(stA - stB), 1e-4f) << "ray " << i;
    }
    // A grid hit's own face and st (bilinear over the grid) are the mesh's for its triangle.
    if (b.face >= 0) {
      ++gridKnows;
      EXPECT_EQ(b.face, t.mesh.triangleFace[b.triangle]) << "ray " << i;
      EXPECT_LT(glm::length(b.st - stB), 1e-5f) << "ray " << i;
    }
  }
  EXPECT_GT(sameTriangle, hits * 99 / 100);
  EXPECT_GT(gridKnows, hits / 2);
}

// DicingSettings::gridsOnly leaves the grids' triangles out of the mesh's arrays: the same points,
// grids and other triangles, and the same hits (face and st from the grid), on a curved surface
// with split faces and on a plane split at the view's border.
TEST(AdaptiveTessellation, GridsOnlyMeshesGiveTheSameHitsWithoutTheGridTriangles) {
  const LimitSurface cube(test::refinedCube(3), SubdivisionScheme::CatmullClark);
  const LimitSurface plane(test::grid(2), SubdivisionScheme::Bilinear);
  const test::WaveDisplacement wave;
  const struct {
    const LimitSurface* surface;
    ScreenMetric screen;
    Vec3 from;  // rays from here to random points of the box [-1, 3]^3
  } cases[] = {{&cube,
                ScreenMetric::lookAt(Vec3(0.4f, 0.3f, 1.9f), Vec3(1.0f, 0.8f, 0.0f), Vec3(0, 1, 0),
                                     40.0f, 320, 180),
                Vec3(0.0f)},
               {&plane,
                ScreenMetric::lookAt(Vec3(1.0f, -0.2f, 0.4f), Vec3(1.0f, 2.0f, 0.0f), Vec3(0, 0, 1),
                                     40.0f, 160, 90),
                Vec3(1.0f, -0.2f, 0.4f)}};
  for (const auto& c : cases) {
    DicingSettings settings;
    const AdaptiveTessellation full = tessellateAdaptive(*c.surface, c.screen, settings, {}, &wave);
    settings.gridsOnly = true;
    const AdaptiveTessellation only = tessellateAdaptive(*c.surface, c.screen, settings, {}, &wave);
    // The grids' triangles and the rest, from the full mesh.
    std::vector<char> inGrid(full.mesh.numTriangles(), 0);
    size_t gridTriangles = 0;
    for (const TriangleGrid& g : full.grids) {
      const size_t n = 2 * size_t(g.width - 1) * (g.height - 1);
      std::fill_n(inGrid.begin() + g.firstTriangle, n, 1);
      gridTriangles += n;
    }
    std::printf(
        "  %zu micropolygons, %zu in %zu grids; %zu stored with gridsOnly, %d faces split\n",
        full.stats.micropolygons, gridTriangles, full.grids.size(), only.mesh.numTriangles(),
        only.stats.facesSplit);
    EXPECT_GT(only.stats.facesSplit, 0);
    EXPECT_GT(gridTriangles, full.mesh.numTriangles() / 2);
    EXPECT_EQ(only.stats.micropolygons, full.stats.micropolygons);
    EXPECT_EQ(only.stats.offScreenMicropolygons, full.stats.offScreenMicropolygons);
    EXPECT_EQ(only.mesh.gridOnlyTriangles, gridTriangles);
    EXPECT_EQ(only.mesh.numTriangles() + gridTriangles, full.mesh.numTriangles());
    EXPECT_TRUE(sameBits(only.mesh.positions, full.mesh.positions));
    ASSERT_EQ(only.grids.size(), full.grids.size());
    for (size_t k = 0; k < full.grids.size(); ++k) {
      const TriangleGrid &a = full.grids[k], &b = only.grids[k];
      EXPECT_EQ(b.firstTriangle, TriangleGrid::kNotInMesh);
      EXPECT_EQ(std::tie(a.firstVertex, a.width, a.height, a.face),
                std::tie(b.firstVertex, b.width, b.height, b.face));
      EXPECT_GE(b.face, 0);
    }
    size_t next = 0;  // the stored triangles are the full mesh's outside grids, in order
    for (size_t t = 0; t < full.mesh.numTriangles() && next < only.mesh.numTriangles(); ++t) {
      if (inGrid[t]) continue;
      EXPECT_EQ(only.mesh.triangleFace[next], full.mesh.triangleFace[t]);
      for (int j = 0; j < 3; ++j) {
        EXPECT_EQ(only.mesh.indices[3 * next + j], full.mesh.indices[3 * t + j]);
        EXPECT_EQ(only.mesh.cornerSt[3 * next + j], full.mesh.cornerSt[3 * t + j]);
      }
      ++next;
    }
    EXPECT_EQ(next, only.mesh.numTriangles());

    RayScene a, b;
    a.addMesh(full.mesh, full.grids);
    b.addMesh(only.mesh, only.grids);
    a.commit();
    b.commit();
    EXPECT_EQ(b.numTriangles(), a.numTriangles());
    Rng rng(123);
    int hits = 0, inGrids = 0;
    for (int i = 0; i < 20000; ++i) {
      const Vec3 to(4.0f * rng.uniform() - 1.0f, 4.0f * rng.uniform() - 1.0f,
                    4.0f * rng.uniform() - 1.0f);
      const Ray ray{c.from, glm::normalize(to - c.from)};
      RayHit ha, hb;
      const bool hitA = a.intersect(ray, ha);
      ASSERT_EQ(hitA, b.intersect(ray, hb)) << "ray " << i;
      if (!hitA) continue;
      ++hits;
      EXPECT_EQ(ha.t, hb.t) << "ray " << i;
      EXPECT_EQ(ha.face, hb.face) << "ray " << i;
      if (hb.face >= 0) {
        ++inGrids;
        EXPECT_EQ(hb.triangle, -1);
        EXPECT_EQ(ha.st, hb.st) << "ray " << i;
      } else {
        ASSERT_GE(hb.triangle, 0);
        EXPECT_EQ(only.mesh.triangleFace[hb.triangle], full.mesh.triangleFace[ha.triangle]);
        EXPECT_EQ(only.mesh.patchCoords(hb.triangle, hb.b1, hb.b2),
                  full.mesh.patchCoords(ha.triangle, ha.b1, ha.b2));
      }
    }
    std::printf("  %d hits, %d in grids\n", hits, inGrids);
    EXPECT_GT(inGrids, hits / 2);
    // A coherent stream of rays (as the integrator traces a tile's) finds the same faces, st and
    // t as single rays, in grids and in the other triangles (a ray through an edge that two
    // triangles share may report either).
    std::vector<Ray> stream(600);
    for (size_t i = 0; i < stream.size(); ++i) {
      const float a = static_cast<float>(i % 30) / 30.0f, b = static_cast<float>(i / 30) / 20.0f;
      stream[i] =
          Ray{c.from, glm::normalize(Vec3(4.0f * a - 1.0f, 4.0f * b - 1.0f, 0.0f) - c.from)};
    }
    std::vector<RayHit> streamed(stream.size());
    std::vector<uint8_t> found(stream.size());
    b.intersect(stream, streamed, found);
    int streamHits = 0, otherFace = 0;
    const auto stOf = [&](const RayHit& h) {
      return h.face >= 0 ? h.st : only.mesh.patchCoords(h.triangle, h.b1, h.b2);
    };
    const auto faceOf = [&](const RayHit& h) {
      return h.face >= 0 ? h.face : only.mesh.triangleFace[h.triangle];
    };
    for (size_t i = 0; i < stream.size(); ++i) {
      RayHit single;
      ASSERT_EQ(found[i] != 0, b.intersect(stream[i], single)) << "ray " << i;
      if (!found[i]) continue;
      ++streamHits;
      EXPECT_NEAR(streamed[i].t, single.t, 1e-5f * single.t) << "ray " << i;
      // A ray through an edge between two faces (ray 225 of the plane meets x = 1 there) may
      // report either face: then both hits are the same point of the limit surface.
      if (faceOf(streamed[i]) == faceOf(single)) {
        EXPECT_NEAR(glm::length(stOf(streamed[i]) - stOf(single)), 0.0f, 1e-4f) << "ray " << i;
      } else {
        const Vec3 p = c.surface->evaluate(faceOf(streamed[i]), stOf(streamed[i])).P;
        const Vec3 q = c.surface->evaluate(faceOf(single), stOf(single)).P;
        EXPECT_LT(glm::length(p - q), 1e-4f) << "ray " << i;
        ++otherFace;
      }
    }
    EXPECT_GT(streamHits, 100);
    EXPECT_LE(otherFace, 2);
    RayScene withoutGrids;
    EXPECT_THROW(withoutGrids.addMesh(only.mesh), Error);
    EXPECT_THROW(withoutGrids.addMesh(only.mesh, {}), Error);
    // Every grid must come along, and a grid left out of the mesh must know its face.
    std::vector<TriangleGrid> some(only.grids.begin() + 1, only.grids.end());
    EXPECT_THROW(withoutGrids.addMesh(only.mesh, some), Error);
    some = only.grids;
    some[0].face = -1;
    EXPECT_THROW(withoutGrids.addMesh(only.mesh, some), Error);
  }
}

// RayScene::takeMesh makes the scene addMesh makes, from the mesh's own points: the same hits to
// the bit, in the room the tessellator leaves after the points or (without it) in a larger array;
// the mesh is left without points, and the scene counts those it holds.
TEST(AdaptiveTessellation, TakenMeshesGiveTheSameHitsAsCopiedOnes) {
  const LimitSurface cube(test::refinedCube(3), SubdivisionScheme::CatmullClark);
  const test::WaveDisplacement wave;
  const ScreenMetric screen = ScreenMetric::lookAt(Vec3(0.4f, 0.3f, 1.9f), Vec3(1.0f, 0.8f, 0.0f),
                                                   Vec3(0, 1, 0), 40.0f, 320, 180);
  DicingSettings settings;
  settings.gridsOnly = true;
  const AdaptiveTessellation t = tessellateAdaptive(cube, screen, settings, {}, &wave);
  ASSERT_GT(t.mesh.numTriangles(), 0u);  // triangles outside the grids, whose points go after
  EXPECT_GE(t.mesh.positions.capacity(), t.mesh.positions.size() + 4 * t.mesh.numTriangles() + 1);
  TessellatedMesh withRoom = t.mesh, without = t.mesh;
  withRoom.positions.reserve(t.mesh.positions.capacity());
  without.positions.shrink_to_fit();
  RayScene copied, taken, takenWithout;
  copied.addMesh(t.mesh, t.grids);
  taken.takeMesh(withRoom, t.grids);
  takenWithout.takeMesh(without, t.grids);
  EXPECT_TRUE(withRoom.positions.empty());
  EXPECT_TRUE(without.positions.empty());
  EXPECT_EQ(copied.heldBytes(), 0u);
  EXPECT_GE(taken.heldBytes(), t.mesh.positions.size() * sizeof(Vec3));
  for (RayScene* scene : {&copied, &taken, &takenWithout}) scene->commit();
  EXPECT_EQ(taken.numPrimitives(), copied.numPrimitives());
  Rng rng(7);
  int hits = 0;
  for (int i = 0; i < 20000; ++i) {
    const Ray ray{Vec3(0.0f), test::randomDirection(rng)};
    RayHit a;
    ASSERT_TRUE(copied.intersect(ray, a));
    ++hits;
    for (const RayScene* scene : {&taken, &takenWithout}) {
      RayHit b;
      ASSERT_TRUE(scene->intersect(ray, b));
      EXPECT_EQ(std::tie(a.t, a.triangle, a.b1, a.b2, a.face),
                std::tie(b.t, b.triangle, b.b1, b.b2, b.face))
          << "ray " << i;
      EXPECT_EQ(a.st, b.st) << "ray " << i;
    }
  }
  EXPECT_EQ(hits, 20000);
}

TEST(AdaptiveTessellation, GridsThatDoNotFitTheMeshThrow) {
  const TessellatedMesh mesh =
      tessellateUniform(LimitSurface(test::cube(), SubdivisionScheme::CatmullClark), 2);
  RayScene scene;
  EXPECT_THROW(scene.addMesh(mesh, {TriangleGrid{0, 0, 40, 2}}), Error);
  EXPECT_THROW(scene.addMesh(mesh, {TriangleGrid{0, 0, 2, 2}, TriangleGrid{0, 1, 2, 2}}), Error);
}

}  // namespace
}  // namespace meso
