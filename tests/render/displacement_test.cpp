// True displacement in the renderer (DESIGN.md sections 3 and 5): the vertex rule and its bound,
// screen-space dicing, the exact limits of partial displacement (disp -> 0 is redistribution,
// disp = 1 is displacement) in the shader and in whole images.
#include "meso/render/displacement.h"
#include "meso/render/film_layout.h"
#include "meso/render/integrator.h"
#include "meso/render/level_shading.h"
#include "meso/relief/fractal_noise.h"
#include "meso/relief/height_table.h"
#include "meso/scene/mesh_io.h"

#include "meso/core/rng.h"

#include "geometry/test_meshes.h"
#include "support/plane_scene.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>

namespace meso {
namespace {

namespace fs = std::filesystem;

const fs::path kTorus = fs::path(MESO_SOURCE_DIR) / "scenes" / "torus.obj";

using testing::noiseLevel;

MaterialRelief levelsOnly(std::vector<ReliefLevelDecl> decls) {
  MaterialRelief r;
  for (const ReliefLevelDecl& d : decls) r.levels.push_back(makeReliefLevel(d));
  return r;
}

Scene planeScene(const std::string& algorithm) {
  Material m;
  m.kd = Vec3(0.7f);
  m.ks = Vec3(0.3f);
  m.phong = 20.0f;
  m.relief = {noiseLevel(0.004f, 1.0f)};
  Scene s = testing::planeScene(testing::writePlaneObj("disp", 4.0f, 0.0f, 8.0f), algorithm, m,
                                Vec3(0.3f, 0.6f, -0.7f), "disp");
  s.camera.position = {0.0f, -1.5f, 1.6f};
  s.camera.lookAt = {0.0f, 0.8f, 0.0f};
  s.camera.width = 48;
  s.camera.height = 32;
  s.camera.fovY = 50.0f;
  s.camera.spp = 2;
  return s;
}

struct Rendered {
  Image image;
  FrameGeometryStats geometry;
  size_t displacedPoints = 0;  // the points the displaced meshes keep after prepareFrame
};

Rendered render(const Scene& scene, bool keepMeshPoints = false) {
  PrepareTimes times;
  RenderContext ctx = prepareRenderContext(scene, times, {.buildFrame = false});
  ctx.keepMeshPoints = keepMeshPoints;
  Rendered out;
  out.geometry = prepareFrame(ctx, scene.camera, times);
  for (const PreparedObject& o : ctx.objects)
    if (o.displaced) out.displacedPoints += o.mesh.positions.size();
  RenderCounters counters;
  out.image = renderFrame(ctx, {scene.camera.spp, 5, false}, counters);
  EXPECT_EQ(counters.nonFinite.load(), 0) << "the renderer's own NaN/Inf check fired";
  return out;
}

double worstBeautyDifference(const Image& a, const Image& b) {
  double worst = 0.0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = FilmLayout::R; c <= FilmLayout::B; ++c)
        worst = std::max(worst, static_cast<double>(std::abs(a.at(x, y, c) - b.at(x, y, c))));
  return worst;
}

// With the frame's view, faceDicing leaves the faces the view cannot see (faceInView, grown by the
// relief's bound) at their defaults, and gives every other face what it gives without the view:
// the tessellation, which reads only the faces it keeps in view, is then the same. On a ground
// seen at a grazing angle, faces just outside the frustum whose relief can rise into it are among
// the evaluated ones.
TEST(Displacement, FaceDicingInAViewSkipsOnlyTheFacesTheViewCannotSee) {
  ControlMesh mesh = test::grid(24);
  mesh.uvs.reserve(mesh.positions.size());
  for (const Vec3& p : mesh.positions) mesh.uvs.emplace_back(p.x / 4.0f, p.y / 4.0f);
  mesh.uvIndices = mesh.faceVertices;
  const LimitSurface surface(mesh, SubdivisionScheme::Bilinear);
  const MaterialRelief relief = levelsOnly({noiseLevel(0.3f, 2.0f, 3), noiseLevel(0.05f, 16.0f)});
  const Vec3 eye(12.0f, -2.0f, 0.6f);
  const ScreenMetric screen =
      ScreenMetric::lookAt(eye, Vec3(12.0f, 12.0f, 0.0f), Vec3(0, 0, 1), 30.0f, 80, 45);
  const TransitionSettings ts;
  const float ppr = screen.pixelsPerUnit(1.0f);  // pixels per radian at the centre
  // (Full mode without the texel floor, which at this grazing view makes millions.)
  for (DisplacementMode mode : {DisplacementMode::ByTransition, DisplacementMode::Full}) {
    const ReliefSampling sampling{mode == DisplacementMode::Full ? 0.0f : 4.0f};
    const FaceDicing all = faceDicing(surface, relief, mode, ts, eye, ppr, sampling);
    const FaceDicing seen =
        faceDicing(surface, relief, mode, ts, eye, ppr, sampling, {}, nullptr, &screen);
    const float bound = displacementBound(relief);
    ASSERT_GT(bound, 0.0f);
    int skipped = 0, grownIn = 0;
    ASSERT_EQ(seen.needsDicing.size(), all.needsDicing.size());
    ASSERT_EQ(seen.raiseDistance.size(), all.raiseDistance.size());
    for (int f = 0; f < surface.numFaces(); ++f) {
      const size_t i = static_cast<size_t>(f);
      if (faceInView(surface, screen, f, bound)) {
        grownIn += !faceInView(surface, screen, f, 0.0f);
        EXPECT_EQ(seen.needsDicing[i], all.needsDicing[i]) << f;
        EXPECT_EQ(seen.texelCap[i], all.texelCap[i]) << f;
        EXPECT_EQ(seen.texelFloor[i], all.texelFloor[i]) << f;
        if (!seen.raiseDistance.empty()) {
          EXPECT_EQ(seen.raiseDistance[i], all.raiseDistance[i]) << f;
        }
        continue;
      }
      ++skipped;
      EXPECT_EQ(seen.needsDicing[i], 0) << f;
      EXPECT_EQ(seen.texelCap[i], 0) << f;
      EXPECT_EQ(seen.texelFloor[i], 0) << f;
    }
    EXPECT_GT(skipped, surface.numFaces() / 4);
    EXPECT_GT(grownIn, 0);
    // The same tessellation, which reads the entries of the faces it keeps in view only.
    const ReliefDisplacement displacement(relief, mode, ts, eye, ppr);
    ASSERT_EQ(displacement.bound(), bound);
    DicingSettings dicing;
    dicing.dicingRate = 4.0f;
    const AdaptiveTessellation a = tessellateAdaptive(surface, screen, dicing, all, &displacement);
    const AdaptiveTessellation b = tessellateAdaptive(surface, screen, dicing, seen, &displacement);
    std::printf("  %zu micropolygons, %d of %d faces skipped, %d in view by the bound only\n",
                a.stats.micropolygons, skipped, surface.numFaces(), grownIn);
    ASSERT_GT(a.stats.micropolygons, 1000u);
    EXPECT_EQ(a.mesh.indices, b.mesh.indices);
    EXPECT_EQ(a.mesh.positions.size(), b.mesh.positions.size());
    EXPECT_TRUE(std::equal(a.mesh.positions.begin(), a.mesh.positions.end(),
                           b.mesh.positions.begin(), b.mesh.positions.end()));
  }
}

// Every vertex of a displaced torus lies within the material's bound of the limit point it came
// from, and the bound is not vacuous (some vertex gets close to it).
TEST(Displacement, EveryVertexStaysWithinTheBound) {
  ControlMesh mesh = loadControlMesh(kTorus);
  const LimitSurface surface(mesh, SubdivisionScheme::CatmullClark);
  const MaterialRelief relief =
      levelsOnly({noiseLevel(0.03f, 2.0f, 3), noiseLevel(0.01f, 9.0f, 2)});
  const Vec3 eye(0.0f, 1.5f, 4.0f);
  const ScreenMetric screen = ScreenMetric::lookAt(eye, Vec3(0.0f), Vec3(0, 1, 0), 40.0f, 160, 90);
  const ReliefDisplacement displacement(relief, DisplacementMode::Full, TransitionSettings{}, eye,
                                        200.0f);
  DicingSettings dicing;
  dicing.dicingRate = 2.0f;
  const AdaptiveTessellation t = tessellateAdaptive(
      surface, screen, dicing, faceDicing(surface, relief, DisplacementMode::Full, {}, eye, 200.0f),
      &displacement);
  const float bound = displacement.bound();
  ASSERT_TRUE(std::isfinite(bound));
  float largest = 0.0f;
  for (size_t c = 0; c < t.mesh.indices.size(); ++c) {
    const Vec3 limit = surface.evaluate(t.mesh.triangleFace[c / 3], t.mesh.cornerSt[c]).P;
    const float d = glm::length(t.mesh.positions[t.mesh.indices[c]] - limit);
    ASSERT_LE(d, bound * 1.0001f + 1e-6f);
    largest = std::max(largest, d);
  }
  std::printf("  bound %.5f, largest offset %.5f over %zu micropolygons\n", bound, largest,
              t.stats.micropolygons);
  EXPECT_GT(largest, 0.25f * bound);
}

// Micropolygons are about a pixel wide. A plane wholly in view gets about a quarter of them from
// twice as far; a plane that fills the view gets about two a pixel from any distance (the parts
// out of view are split off and diced coarsely). A camera far enough that T stays below e3 leaves
// auto mode with the coarse tessellation only.
TEST(Displacement, MicropolygonsFollowTheScreenAndTheTransition) {
  Scene s = planeScene("displacement");
  s.materials[0].relief = {noiseLevel(0.004f, 16.0f)};  // texels far below a pixel: no texel cap
  s.camera.lookAt = {0.0f, 0.0f, 0.0f};
  s.camera.up = {0.0f, 1.0f, 0.0f};
  s.camera.fovY = 20.0f;  // the plane (8 units) fills the view from 2 and 4, not from 30 and 60
  s.render.reliefSamples = 0.0f;  // pixel dicing only (the floor is the next test's)
  size_t count[4];
  const float distances[4] = {30.0f, 60.0f, 2.0f, 4.0f};
  for (int k = 0; k < 4; ++k) {
    s.camera.position = {0.0f, 0.0f, distances[k]};
    count[k] = render(s).geometry.micropolygons;
  }
  const double pixels = double(s.camera.width) * s.camera.height;
  std::printf(
      "  wholly in view, distance 30: %zu micropolygons, 60: %zu (ratio %.3f)\n"
      "  filling the view (%.0f pixels), distance 2: %zu, 4: %zu\n",
      count[0], count[1], double(count[1]) / count[0], pixels, count[2], count[3]);
  EXPECT_GT(static_cast<double>(count[1]) / count[0], 0.2);
  EXPECT_LT(static_cast<double>(count[1]) / count[0], 0.32);
  // Two a pixel, and at most four times that where sub-quads straddle the view's border.
  for (int k : {2, 3}) {
    EXPECT_GT(static_cast<double>(count[k]), 2.0 * pixels) << distances[k];
    EXPECT_LT(static_cast<double>(count[k]), 8.0 * pixels) << distances[k];
  }

  Scene distant = planeScene("auto");
  distant.camera.position = {0.0f, 0.0f, 400.0f};
  distant.camera.lookAt = {0.0f, 0.0f, 0.0f};
  distant.camera.up = {0.0f, 1.0f, 0.0f};
  const Rendered r = render(distant);
  EXPECT_EQ(r.geometry.facesDiced, 0);
  EXPECT_LE(r.geometry.micropolygons, 8u) << "one quad, no dicing";
  EXPECT_TRUE(r.image.allFinite());
}

// Full displacement resolves relief below a pixel where it masks itself: seen at a grazing angle,
// every edge of the one-face plane gets render.relief_samples segments per shortest wavelength
// (the floor), however far the camera, while pixel dicing alone (relief_samples 0) thins out with
// distance. Seen face-on nothing is masked, and the floor does not apply.
TEST(Displacement, ReliefSamplesFloorResolvesSubPixelReliefWhereItMasks) {
  Scene s = planeScene("displacement");
  s.materials[0].relief = {noiseLevel(0.02f, 1.0f)};
  const MaterialRelief relief = levelsOnly(s.materials[0].relief);
  const float perU = relief.levels[0].freqPerU, slope = reliefSlopeRmsPerU(relief);
  ASSERT_GT(perU, 0.0f);
  // The premises: the plane (uv 0..8 over 8 units, unit speed) masks at cot(theta_V) = 0.1, not
  // face-on.
  ASSERT_GT(3.0f * slope, 0.1f * 1.5f);
  const size_t floorRate = static_cast<size_t>(std::ceil(4.0f * perU * 8.0f));
  s.camera.lookAt = {0.0f, 0.0f, 0.0f};
  s.camera.up = {0.0f, 0.0f, 1.0f};
  s.camera.fovY = 20.0f;
  size_t floored[3], pixel[3];
  const Vec3 eyes[3] = {{0.0f, -30.0f, 3.0f}, {0.0f, -60.0f, 6.0f}, {0.0f, 0.5f, 30.0f}};
  for (int k = 0; k < 3; ++k) {
    s.camera.position = eyes[k];
    s.render.reliefSamples = 4.0f;
    floored[k] = render(s).geometry.micropolygons;
    s.render.reliefSamples = 0.0f;
    pixel[k] = render(s).geometry.micropolygons;
  }
  std::printf(
      "  rms slope %.3f, floor rate %zu: %zu, %zu and %zu micropolygons; pixel dicing %zu, "
      "%zu and %zu\n",
      slope, floorRate, floored[0], floored[1], floored[2], pixel[0], pixel[1], pixel[2]);
  EXPECT_EQ(floored[0], 2 * floorRate * floorRate);
  EXPECT_EQ(floored[1], 2 * floorRate * floorRate);
  EXPECT_LT(pixel[1], pixel[0]);
  EXPECT_LT(pixel[0], floored[0]);
  EXPECT_EQ(floored[2], pixel[2]);  // face-on: no masking, no floor
}

// The rms slope is that of the relief's heights: it scales with amplitude and frequency, adds in
// quadrature over levels, and is 0 for a flat relief.
TEST(Displacement, ReliefSlopeRmsScalesWithAmplitudeAndFrequency) {
  const float one = reliefSlopeRmsPerU(levelsOnly({noiseLevel(0.01f, 1.0f)}));
  EXPECT_GT(one, 0.0f);
  EXPECT_NEAR(reliefSlopeRmsPerU(levelsOnly({noiseLevel(0.03f, 1.0f)})), 3.0f * one, 1e-4f * one);
  const float fine = reliefSlopeRmsPerU(levelsOnly({noiseLevel(0.01f, 4.0f)}));
  EXPECT_NEAR(fine, 4.0f * one, 0.25f * one);  // other sample points of the same statistics
  EXPECT_NEAR(reliefSlopeRmsPerU(levelsOnly({noiseLevel(0.01f, 1.0f), noiseLevel(0.01f, 4.0f)})),
              std::sqrt(one * one + fine * fine), 1e-3f * fine);
  EXPECT_EQ(reliefSlopeRmsPerU(levelsOnly({noiseLevel(0.0f, 1.0f)})), 0.0f);
}

// The shader's partial displacement: n' = R_thetaV(R_thetaW^-1(n)) is plain redistribution at
// disp = 0, tends to it continuously as disp -> 0, and is the Blinn normal itself at disp = 1.
TEST(Displacement, PartialDisplacementHasExactLimits) {
  Scene s = planeScene("redistribution");
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(s, times, {.buildFrame = false});
  const Redistribution& r = ctx.reliefs[0].tables(0).redistribution;
  Rng rng(4);
  for (int k = 0; k < 200; ++k) {
    const Vec3 N(0.0f, 0.0f, 1.0f);
    const float thetaV = 0.05f + 1.4f * rng.uniform();
    const Vec3 V(std::sin(thetaV), 0.0f, std::cos(thetaV));
    const ViewFrame f = makeViewFrame(N, V, Vec3(1, 0, 0));
    const Vec3 nBump =
        glm::normalize(Vec3(0.4f * (rng.uniform() - 0.5f), 0.4f * (rng.uniform() - 0.5f), 1.0f));
    const Vec3 atZero = redistributeNormal(r, f, 0.0f, nBump);
    EXPECT_EQ(redistributeNormal(r, f, 1.0f, nBump), nBump);
    EXPECT_LT(glm::length(redistributeNormal(r, f, 1e-4f, nBump) - atZero), 2e-3f);
    EXPECT_LT(glm::length(redistributeNormal(r, f, 1e-6f, nBump) - atZero), 2e-4f);
    EXPECT_TRUE(isFinite(redistributeNormal(r, f, 0.999999f, nBump)));
  }
}

// Whole images: with thresholds that keep T between e2 and e3 everywhere, auto is the
// redistribution renderer (nothing is raised); with D = 0 and e3, e4 tiny, T exceeds e4
// everywhere and auto is the displacement renderer, to float rounding.
TEST(Displacement, AutoImagesMatchTheirLimits) {
  Scene autoRedist = planeScene("auto");
  autoRedist.render.transition = {2.0f, 0.1f, -3e6f, -2e6f, 2e6f, 3e6f};
  const Rendered a = render(autoRedist), b = render(planeScene("redistribution"));
  EXPECT_EQ(a.geometry.facesDiced, 0) << "nothing raised: the coarse tessellation";
  EXPECT_LE(a.geometry.micropolygons, 8u);
  EXPECT_LT(worstBeautyDifference(a.image, b.image), 1e-4);

  Scene autoDisp = planeScene("auto");
  autoDisp.render.transition = {0.0f, 0.1f, -2.0f, -1.0f, 1e-6f, 2e-6f};
  autoDisp.render.acrossViewCap = 1.0f;  // full displacement keeps the whole cap both ways
  Scene disp = planeScene("displacement");
  disp.render.transition = autoDisp.render.transition;
  disp.render.reliefSamples = 0.0f;  // the hybrid dices by pixels only where it displaces
  const Rendered c = render(autoDisp), d = render(disp);
  EXPECT_GT(c.geometry.micropolygons, 1000u);
  EXPECT_EQ(c.geometry.micropolygons, d.geometry.micropolygons);
  EXPECT_LT(worstBeautyDifference(c.image, d.image), 1e-5);
  // With the default share the hybrid dices edges across this grazing view more coarsely where
  // the cap binds (AdaptiveTessellation.AcrossViewCapHalvesTheCapAcrossAGrazingViewOnly), and
  // changes the image by far less than the renderers differ (below).
  autoDisp.render.acrossViewCap = Scene{}.render.acrossViewCap;
  const Rendered e = render(autoDisp);
  EXPECT_LT(e.geometry.micropolygons, c.geometry.micropolygons);
  EXPECT_LT(worstBeautyDifference(c.image, e.image), 4e-4);
  // And the two limits really differ from each other (the test is not vacuous).
  EXPECT_GT(worstBeautyDifference(a.image, c.image),
            4e-4);  // 40 times the tolerance above; measured 0.0010 (gcc), 0.00099 (clang)
}

// Shading reads a displaced triangle's face and patch coordinates only: the meshes' points and
// indices, which Embree has copied, are released before the BVH build, and the image is the same
// bits as with them kept.
TEST(Displacement, ReleasingTheMeshPointsKeepsTheImage) {
  for (const char* algorithm : {"auto", "displacement"}) {
    Scene s = planeScene(algorithm);
    s.render.transition.D = 0.5f;  // auto raises the relief over part of the plane
    const Rendered kept = render(s, true), released = render(s);
    ASSERT_GT(kept.geometry.micropolygons, 1000u) << algorithm;
    EXPECT_GT(kept.displacedPoints, kept.geometry.micropolygons / 4) << algorithm;
    EXPECT_EQ(released.displacedPoints, 0u) << algorithm;
    EXPECT_EQ(released.geometry.micropolygons, kept.geometry.micropolygons) << algorithm;
    // Points (12 bytes) and indices are gone from what meso keeps.
    EXPECT_LE(released.geometry.meshBytes + 12 * kept.displacedPoints, kept.geometry.meshBytes)
        << algorithm;
    EXPECT_EQ(worstBeautyDifference(kept.image, released.image), 0.0) << algorithm;
  }
}

// `meso render` frees geometry no later frame reuses before it encodes a frame's images: nothing
// of it is left, and a frame prepared again is made anew and renders the same bits (undisplaced
// objects, otherwise kept from frame to frame, included).
TEST(Displacement, ReleasedFrameGeometryIsMadeAgain) {
  for (const char* algorithm : {"auto", "bump"}) {
    Scene s = planeScene(algorithm);
    s.render.transition.D = 0.5f;
    PrepareTimes times;
    RenderContext ctx = prepareRenderContext(s, times, {.buildFrame = false});
    RenderCounters counters;
    const FrameGeometryStats first = prepareFrame(ctx, s.camera, times);
    const Image before = renderFrame(ctx, {s.camera.spp, 5, false}, counters);
    ASSERT_GT(ctx.numTriangles(), 0u) << algorithm;
    releaseFrameGeometry(ctx);
    EXPECT_EQ(ctx.numTriangles(), 0u) << algorithm;
    for (const PreparedObject& o : ctx.objects) {
      EXPECT_EQ(o.mesh.numTriangles(), 0u) << algorithm;
      EXPECT_TRUE(o.grids.empty()) << algorithm;
    }
    const FrameGeometryStats again = prepareFrame(ctx, s.camera, times);
    EXPECT_TRUE(again.rebuilt) << algorithm;
    EXPECT_EQ(again.triangles, first.triangles) << algorithm;
    const Image after = renderFrame(ctx, {s.camera.spp, 5, false}, counters);
    EXPECT_EQ(worstBeautyDifference(before, after), 0.0) << algorithm;
  }
}

// Facet normals of the displaced micropolygons approach the Blinn normal of the relief (the
// paper's shading normal) as the dicing rate shrinks.
TEST(Displacement, FacetNormalsApproachTheBlinnNormal) {
  Scene s = planeScene("displacement");
  // Shortest wavelength about 3.4 pixels: 8 samples per wavelength (the cap) is about 0.42 px.
  s.camera.position = {0.0f, 0.0f, 2.5f};
  s.camera.lookAt = {0.0f, 0.0f, 0.0f};
  s.camera.up = {0.0f, 1.0f, 0.0f};
  s.camera.width = 64;
  s.camera.height = 64;
  s.render.reliefSamples = 0.0f;  // dicing by pixels only, so the rate decides
  double previous = 1e9;
  for (float rate : {4.0f, 1.0f, 0.25f}) {
    s.render.dicingRate = rate;
    PrepareTimes times;
    RenderContext ctx = prepareRenderContext(s, times, {.buildFrame = false});
    ctx.keepMeshPoints = true;
    prepareFrame(ctx, s.camera, times);
    const PreparedObject& o = ctx.objects[0];
    const ReliefLevel& level = ctx.reliefs[0].levels[0];
    double sum = 0.0;
    size_t count = 0, seen = 0;
    const auto facetVsBlinn = [&](int face, Vec3 p0, Vec3 p1, Vec3 p2, Vec2 st) {
      if (seen++ % 7) return;
      const Vec3 facet = glm::normalize(glm::cross(p1 - p0, p2 - p0));
      const SurfacePoint sp = o.surface.evaluate(face, st);
      const Vec2 B = level.derivatives(sp.uv);
      const Vec3 blinn = blinnNormal(sp.Pu, sp.Pv, sp.N, B.x, B.y);
      sum += std::acos(std::clamp(glm::dot(facet, blinn), -1.0f, 1.0f));
      ++count;
    };
    const std::vector<Vec3>& P = o.mesh.positions;
    for (size_t t = 0; t < o.mesh.numTriangles(); ++t) {
      const uint32_t* k = &o.mesh.indices[3 * t];
      facetVsBlinn(o.mesh.triangleFace[t], P[k[0]], P[k[1]], P[k[2]],
                   o.mesh.patchCoords(t, 1.0f / 3, 1.0f / 3));
    }
    // The triangles only the grids hold: cell (i, j)'s two, split as TriangleGrid says.
    for (const TriangleGrid& g : o.grids) {
      if (g.firstTriangle != TriangleGrid::kNotInMesh) continue;
      const auto at = [&](int i, int j) { return P[g.firstVertex + size_t(j) * g.width + i]; };
      for (int j = 0; j + 1 < g.height; ++j)
        for (int i = 0; i + 1 < g.width; ++i) {
          facetVsBlinn(g.face, at(i, j), at(i + 1, j), at(i, j + 1),
                       (g.stAt(i, j) + g.stAt(i + 1, j) + g.stAt(i, j + 1)) / 3.0f);
          facetVsBlinn(g.face, at(i + 1, j + 1), at(i, j + 1), at(i + 1, j),
                       (g.stAt(i + 1, j + 1) + g.stAt(i, j + 1) + g.stAt(i + 1, j)) / 3.0f);
        }
    }
    EXPECT_EQ(seen, o.mesh.numMicropolygons());
    const double mean = degrees(static_cast<float>(sum / count));
    std::printf(
        "  dicing rate %.2f px: %zu micropolygons, mean angle facet vs Blinn %.3f degrees\n", rate,
        o.mesh.numMicropolygons(), mean);
    EXPECT_LT(mean, 0.7 * previous);
    previous = mean;
  }
}

}  // namespace
}  // namespace meso

namespace meso {
namespace {

// One unit quad in the plane z = 0, centred on the origin, uv over [0, 1]^2.
LimitSurface unitQuad() {
  ControlMesh mesh;
  mesh.positions = {Vec3(-0.5f, -0.5f, 0), Vec3(0.5f, -0.5f, 0), Vec3(0.5f, 0.5f, 0),
                    Vec3(-0.5f, 0.5f, 0)};
  mesh.faceSizes = {4};
  mesh.faceVertices = {0, 1, 2, 3};
  mesh.uvs = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
  mesh.uvIndices = {0, 1, 2, 3};
  return LimitSurface(mesh, SubdivisionScheme::Bilinear);
}

// A height image whose texels carry detail finer than its level's wavelength (sharp edges,
// per-texel noise): where the hybrid raises it on a face seen at grazing, the face gets full
// displacement's floor (relief_samples edges per texel-scale wavelength, up to one edge per
// texel), so that texel-scale relief masks itself as on the converged surface; seen face-on, not
// raised (far away), or procedural (the pixels resolve its one wavelength where it is raised), it
// gets none. A band of a split image gets the floor at its own wavelength where it is the finest
// band raised on the face.
TEST(Displacement, HybridFloorsAHeightImageWithTexelDetailWhereItMasks) {
  const LimitSurface surface = unitQuad();
  constexpr int kTexels = 64;
  std::vector<float> texels(kTexels * kTexels);
  Rng rng(3);
  for (float& t : texels) t = rng.uniform();  // detail up to the texels' Nyquist limit
  const auto imageRelief = [&](float freqPerU) {
    MaterialRelief r;
    ReliefLevel image;
    image.source = std::make_unique<HeightTable>(kTexels, kTexels, texels);
    image.amplitude = 0.02f;
    image.scale = 1.0f;
    image.freqPerU = freqPerU;
    r.levels.push_back(std::move(image));
    return r;
  };
  const MaterialRelief coarse = imageRelief(4.0f);  // a level measured at 4 cycles per u
  ASSERT_GT(coarse.levels[0].source->highestFrequency(), 4.0f * coarse.levels[0].freqPerU);
  const ReliefSampling sampling{4.0f};
  const TransitionSettings ts;
  const Vec3 grazing(0.0f, -3.0f, 0.2f), faceOn(0.0f, 0.0f, 3.0f);
  const auto floorOf = [&](const MaterialRelief& r, DisplacementMode mode, Vec3 eye, float ppr) {
    const FaceDicing d = faceDicing(surface, r, mode, ts, eye, ppr, sampling);
    return std::pair(d.texelFloor[0], d.needsDicing[0]);
  };
  const auto [full, fullDiced] = floorOf(coarse, DisplacementMode::Full, grazing, 2000.0f);
  EXPECT_EQ(full, 2 * kTexels);  // 4 per texel-scale wavelength of two texels
  const auto [hybrid, raised] = floorOf(coarse, DisplacementMode::ByTransition, grazing, 2000.0f);
  EXPECT_EQ(raised, 1);
  EXPECT_EQ(hybrid, kTexels);  // the hybrid's floor stops at one edge per texel
  // unless render.texel_samples asks for more
  EXPECT_EQ(faceDicing(surface, coarse, DisplacementMode::ByTransition, ts, grazing, 2000.0f,
                       ReliefSampling{4.0f, 2.0f})
                .texelFloor[0],
            full);
  EXPECT_EQ(floorOf(coarse, DisplacementMode::ByTransition, faceOn, 2000.0f).first, 0);
  const auto [far, farRaised] = floorOf(coarse, DisplacementMode::ByTransition, grazing, 0.5f);
  EXPECT_EQ(farRaised, 0);
  EXPECT_EQ(far, 0);
  // A level measured at the image's own finest frequency (the finest band of a split image) is
  // floored too, up to the texel cap: one edge per pixel there is about one per texel.
  const MaterialRelief fine = imageRelief(coarse.levels[0].source->highestFrequency());
  EXPECT_EQ(floorOf(fine, DisplacementMode::ByTransition, grazing, 2000.0f).first, 2 * kTexels);
  // A coarser band of a split image raised where its finer band is not: relief_samples edges per
  // its own wavelength (4 per u here, on a face one u wide).
  MaterialRelief split = imageRelief(4.0f);
  split.levels.push_back(std::move(imageRelief(2000.0f).levels[0]));
  EXPECT_EQ(floorOf(split, DisplacementMode::ByTransition, grazing, 2000.0f).first, 16);
  const MaterialRelief noise = levelsOnly({noiseLevel(0.02f, 1.0f)});
  EXPECT_EQ(floorOf(noise, DisplacementMode::ByTransition, grazing, 2000.0f).first, 0);
  EXPECT_GT(floorOf(noise, DisplacementMode::Full, grazing, 2000.0f).first, 0);
}

// The texel cap of a height image: relief_samples edges per shortest wavelength (two texels), at
// least one per texel, refined with them (a reference that doubles them dices each texel in
// four), while noise keeps its samples per wavelength.
TEST(Displacement, HeightImageTexelCapIsRefinedWithReliefSamples) {
  ReliefLevel image;
  image.source = std::make_unique<HeightTable>(32, 16, std::vector<float>(32 * 16, 0.5f));
  image.scale = 3.0f;
  EXPECT_FLOAT_EQ(samplesPerU(image, {0.0f}), 96.0f);
  EXPECT_FLOAT_EQ(samplesPerU(image, {2.0f}), 96.0f);
  EXPECT_FLOAT_EQ(samplesPerU(image, {4.0f}), 192.0f);
  EXPECT_FLOAT_EQ(samplesPerU(image, {8.0f}), 384.0f);
  EXPECT_FLOAT_EQ(samplesPerU(image, {16.0f}), 768.0f);
  // render.texel_samples overrides it, for images only.
  EXPECT_FLOAT_EQ(samplesPerU(image, {4.0f, 8.0f}), 768.0f);
  EXPECT_FLOAT_EQ(samplesPerU(image, {16.0f, 1.0f}), 96.0f);
  ReliefLevel noise;
  noise.source = std::make_unique<FractalNoise>(FractalNoiseOptions{});
  noise.freqPerU = 10.0f;
  EXPECT_FLOAT_EQ(samplesPerU(noise, {4.0f}), 80.0f);
  EXPECT_FLOAT_EQ(samplesPerU(noise, {8.0f}), 160.0f);
  EXPECT_FLOAT_EQ(samplesPerU(noise, {8.0f, 16.0f}), 160.0f);
}

}  // namespace
}  // namespace meso

namespace meso {
namespace {

// A level of a height image takes D * kHeightImageDScale (1 at render.D 2), a procedural level D:
// at the same wavelength, 1.5 pixels per wavelength raises T above 0 for the image and leaves it
// below for the noise, in levelTransition and in faceDicing's test of whether a face is raised.
TEST(Displacement, HeightImageLevelsTakeAScaledD) {
  ReliefLevel image;
  image.source = std::make_unique<HeightTable>(16, 16, std::vector<float>(16 * 16, 0.5f));
  image.amplitude = 0.001f;
  image.freqPerU = 100.0f;
  // One octave: T of its only wavelength (several octaves hold T at 0 while their longest spans
  // more than D pixels: Transition.OctavesThatSpanPixelsKeepTheTablesAway).
  MaterialRelief noiseRelief = levelsOnly({noiseLevel(0.001f, 1.0f, 1)});
  ReliefLevel& noise = noiseRelief.levels[0];
  noise.freqPerU = 100.0f;
  const TransitionSettings ts;
  ASSERT_EQ(ts.D, 2.0f);
  EXPECT_EQ(levelD(image, ts), 2.0f * kHeightImageDScale);
  EXPECT_EQ(levelD(noise, ts), 2.0f);
  // nu = 0.01 * 1000 / (20 / 3) = 1.5 pixels, seen face-on: T = (nu - D) / (1 + eps).
  const float d = 20.0f / 3.0f;
  EXPECT_NEAR(levelTransition(image, 1.0f, 1.0f, d, 1000.0f, ts), (1.5f - 1.0f) / 1.1f, 1e-5f);
  EXPECT_NEAR(levelTransition(noise, 1.0f, 1.0f, d, 1000.0f, ts), (1.5f - 2.0f) / 1.1f, 1e-5f);

  const LimitSurface surface = unitQuad();
  // From 10 units, at most 0.01 * 1.25 * 1000 / 10 = 1.25 pixels per wavelength: between the least
  // nu T raises an image level at (1 + e3 eps = 1.03) and a procedural one's (2.03).
  MaterialRelief imageRelief;
  imageRelief.levels.push_back(std::move(image));
  const auto raised = [&](const MaterialRelief& r) {
    return faceDicing(surface, r, DisplacementMode::ByTransition, ts, Vec3(0.0f, 0.0f, 10.0f),
                      1000.0f, ReliefSampling{})
        .needsDicing[0];
  };
  EXPECT_EQ(raised(imageRelief), 1);
  EXPECT_EQ(raised(noiseRelief), 0);
}

}  // namespace
}  // namespace meso
