// Solid relief at render time (docs/solid-relief.md): the chart that replaces the parameterization,
// the first-order normal of the displaced surface, T in world units and the object's solid space.
#include "meso/render/transition.h"

#include "geometry/test_meshes.h"
#include "meso/geometry/limit_surface.h"
#include "support/plane_scene.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>

namespace meso {
namespace {

MaterialRelief solidRelief(float amplitude, float cells) {
  MaterialRelief relief;
  relief.levels.push_back(makeReliefLevel(testing::solidLevel(amplitude, cells, 3, 4)));
  return relief;
}

SolidSpace worldSpace() {
  SolidSpace s;
  s.active = true;
  return s;
}

// The first-order normal that the levels' frames carry (the 3-D gradient projected on the tangent
// plane) is the normal of the displaced surface P + h(P) N: exactly on a plane, whatever its
// parameterization (here stretched and sheared), and to first order in h on a sphere.
TEST(SolidRelief, ProjectedNormalIsTheDisplacedSurfaceNormal) {
  const MaterialRelief relief = solidRelief(0.05f, 4.0f);
  const ReliefLevel& level = relief.levels[0];
  const auto height = [&](Vec3 P) {
    return level.amplitude * (level.solid->height(level.solidCells * P) - level.midlevel);
  };
  const TransitionSettings ts;
  const Vec3 eye(0.0f, 0.0f, 50.0f);
  const Vec3 a(2.0f, 0.3f, 0.1f), b(0.5f, 1.5f, -0.2f);
  const Vec3 N = glm::normalize(glm::cross(a, b));
  double worst = 0.0, tilt = 0.0;
  for (int k = 0; k < 50; ++k) {
    const Vec2 uv(0.037f * k, 0.21f - 0.013f * k);
    const SurfacePoint sp{uv.x * a + uv.y * b, a, b, N, uv};
    ReliefCoord coord;
    const SurfacePoint chart = reliefChart(sp, worldSpace(), coord);
    const LevelTransitions t =
        levelTransitions(relief, chart, coord, eye, 500.0f, ts, DisplacementMode::Full);
    ASSERT_EQ(t.raised, 1);
    EXPECT_NEAR(t.H[0], height(sp.P), 1e-6f);
    // Central differences of the displaced plane along its own (u, v).
    const float e = 1e-3f;
    const auto D = [&](Vec2 w) {
      const Vec3 P = (uv.x + w.x) * a + (uv.y + w.y) * b;
      return P + height(P) * N;
    };
    const Vec3 Du = (D({e, 0}) - D({-e, 0})) / (2 * e), Dv = (D({0, e}) - D({0, -e})) / (2 * e);
    const Vec3 exact = glm::normalize(glm::cross(Du, Dv));
    worst = std::max(worst, static_cast<double>(glm::length(exact - t.frames[1].N)));
    tilt = std::max(tilt, static_cast<double>(glm::length(N - t.frames[1].N)));
  }
  EXPECT_LT(worst, 2e-3);
  EXPECT_GT(tilt, 0.1);  // the relief does tilt the normal: the comparison is not vacuous

  // A unit sphere with a small relief: displaced P + h(P) N(P), N the radial direction.
  const MaterialRelief fine = solidRelief(0.002f, 4.0f);
  const ReliefLevel& small = fine.levels[0];
  double sphereWorst = 0.0;
  for (int k = 0; k < 50; ++k) {
    const float th = 0.3f + 0.05f * k, ph = 0.7f * k;
    const auto point = [&](float t, float p) {
      return Vec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
    };
    const auto D = [&](float t, float p) {
      const Vec3 P = point(t, p);
      return P + small.amplitude * (small.solid->height(small.solidCells * P) - small.midlevel) * P;
    };
    const float e = 1e-3f;
    const Vec3 Pt = (point(th + e, ph) - point(th - e, ph)) / (2 * e);
    const Vec3 Pp = (point(th, ph + e) - point(th, ph - e)) / (2 * e);
    const SurfacePoint sp{point(th, ph), Pt, Pp, point(th, ph), Vec2(0.0f)};
    ReliefCoord coord;
    const SurfacePoint chart = reliefChart(sp, worldSpace(), coord);
    const LevelTransitions t =
        levelTransitions(fine, chart, coord, eye, 500.0f, ts, DisplacementMode::Full);
    const Vec3 exact = glm::normalize(glm::cross((D(th + e, ph) - D(th - e, ph)) / (2 * e),
                                                 (D(th, ph + e) - D(th, ph - e)) / (2 * e)));
    sphereWorst = std::max(sphereWorst, static_cast<double>(glm::length(exact - t.frames[1].N)));
  }
  // First order: the neglected term is h times the curvature, about 0.002.
  EXPECT_LT(sphereWorst, 5e-3);
}

// T and the frames of a solid level do not depend on the parameterization: the same point with
// P_u ten times longer and P_v sheared gives the same T and normals; uv relief (the control) does
// not.
TEST(SolidRelief, TransitionIgnoresTheParameterization) {
  const MaterialRelief solid = solidRelief(0.01f, 8.0f);
  MaterialRelief uv;
  uv.levels.push_back(makeReliefLevel(testing::noiseLevel(0.01f, 8.0f, 3)));
  const TransitionSettings ts;
  const Vec3 eye(0.3f, 2.0f, 3.0f);
  const Vec3 N(0, 0, 1);
  const SurfacePoint plain{Vec3(0.2f, 0.1f, 0.0f), Vec3(1, 0, 0), Vec3(0, 1, 0), N,
                           Vec2(0.2f, 0.1f)};
  SurfacePoint stretched = plain;
  stretched.Pu = Vec3(10, 0, 0);
  stretched.Pv = Vec3(3, 1, 0);
  ReliefCoord c0, c1;
  const SurfacePoint a = reliefChart(plain, worldSpace(), c0);
  const SurfacePoint b = reliefChart(stretched, worldSpace(), c1);
  const LevelTransitions ta =
      levelTransitions(solid, a, c0, eye, 800.0f, ts, DisplacementMode::ByTransition);
  const LevelTransitions tb =
      levelTransitions(solid, b, c1, eye, 800.0f, ts, DisplacementMode::ByTransition);
  EXPECT_NEAR(ta.T[0], tb.T[0], 1e-4f * std::abs(ta.T[0]));
  EXPECT_LT(glm::length(ta.frames[1].N - tb.frames[1].N), 1e-5f);
  const float uvPlain =
      levelTransitions(uv, plain, eye, 800.0f, ts, DisplacementMode::ByTransition).T[0];
  const float uvStretched =
      levelTransitions(uv, stretched, eye, 800.0f, ts, DisplacementMode::ByTransition).T[0];
  EXPECT_GT(std::abs(uvStretched - uvPlain), 0.5f * std::abs(uvPlain));
}

// A degenerate parameterization (a pole: P_u = 0, or both tangents zero) still gives an orthonormal
// chart and finite heights.
TEST(SolidRelief, ChartAtDegenerateTangents) {
  const Vec3 N = glm::normalize(Vec3(0.2f, -0.3f, 1.0f));
  for (const auto& [Pu, Pv] : {std::pair{Vec3(0.0f), Vec3(0, 1, 0)},
                               std::pair{Vec3(0.0f), Vec3(0.0f)}, std::pair{N, 2.0f * N}}) {
    ReliefCoord coord;
    const SurfacePoint c = reliefChart({Vec3(0.5f), Pu, Pv, N, Vec2(0.0f)}, worldSpace(), coord);
    EXPECT_NEAR(glm::length(c.Pu), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::length(c.Pv), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(c.Pu, c.Pv), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(c.Pu, N), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(glm::cross(c.Pu, c.Pv), N), 1.0f, 1e-5f);
  }
}

// Object space: the object's transform is undone, and one unit of it is as long in the world as
// the transform's (even) scale; uneven scale warns.
TEST(SolidRelief, ObjectSpaceUndoesTheTransform) {
  Material m;
  m.relief.push_back(testing::solidLevel(0.01f, 4.0f));
  Mat4 t(1.0f);
  t = glm::translate(t, Vec3(1.0f, 2.0f, 3.0f));
  t = glm::rotate(t, 0.6f, Vec3(0.0f, 1.0f, 0.0f));
  t = glm::scale(t, Vec3(2.0f));
  std::string warning;
  const SolidSpace s = solidSpace(m, t, &warning);
  ASSERT_TRUE(s.active);
  EXPECT_TRUE(warning.empty());
  EXPECT_NEAR(s.lengthPerUnit, 2.0f, 1e-5f);
  const Vec3 object(0.3f, -0.2f, 0.5f);
  const Vec3 world = Vec3(t * Vec4(object, 1.0f));
  EXPECT_LT(glm::length(s.linear * world + s.offset - object), 1e-5f);
  // The chart's tangents are one unit of object space long.
  ReliefCoord coord;
  reliefChart({world, Vec3(1, 0, 0), Vec3(0, 0, 1), Vec3(0, 1, 0), Vec2(0.0f)}, s, coord);
  EXPECT_NEAR(glm::length(coord.pu), 1.0f, 1e-5f);
  EXPECT_NEAR(glm::length(coord.pv), 1.0f, 1e-5f);
  m.relief[0].worldSpace = true;
  EXPECT_EQ(solidSpace(m, t, nullptr).lengthPerUnit, 1.0f);
  m.relief[0].worldSpace = false;
  solidSpace(m, glm::scale(Mat4(1.0f), Vec3(1.0f, 3.0f, 1.0f)), &warning);
  EXPECT_NE(warning.find("unevenly"), std::string::npos);
  Material uv;
  uv.relief.push_back(testing::noiseLevel(0.01f, 4.0f));
  EXPECT_FALSE(solidSpace(uv, t, nullptr).active);
}

// No seams on a mesh without texture coordinates: along every edge of a Catmull-Clark cube (each
// face its own (s, t) chart), both faces give solid relief the same height and the same first-order
// normal; relief over (u, v) follows each face's chart and breaks there (the control).
TEST(SolidRelief, NoSeamsAcrossTheFacesOfAMeshWithoutUv) {
  const ControlMesh mesh = test::cube();
  const LimitSurface surface(mesh, SubdivisionScheme::CatmullClark);
  const MaterialRelief solid = solidRelief(0.03f, 3.0f);
  MaterialRelief uv;
  uv.levels.push_back(makeReliefLevel(testing::noiseLevel(0.03f, 3.0f, 3)));
  const TransitionSettings ts;
  const Vec3 eye(0.0f, 0.0f, 30.0f);
  const auto corner = [&](int f, int k) { return mesh.faceVertices[4 * f + (k % 4)]; };
  double solidWorst = 0.0, uvWorst = 0.0, normalWorst = 0.0;
  int edges = 0;
  for (int f = 0; f < 6; ++f)
    for (int k = 0; k < 4; ++k)
      for (int g = 0; g < 6; ++g)
        for (int j = 0; j < 4; ++j) {
          // The same edge seen from face g, in the opposite direction.
          if (g == f || corner(g, j) != corner(f, k + 1) || corner(g, j + 1) != corner(f, k))
            continue;
          ++edges;
          for (float t : {0.2f, 0.5f, 0.8f}) {
            const Vec2 a = glm::mix(surface.cornerSt(f, k), surface.cornerSt(f, (k + 1) % 4), t);
            const Vec2 b = glm::mix(surface.cornerSt(g, (j + 1) % 4), surface.cornerSt(g, j), t);
            const SurfacePoint pa = surface.evaluate(f, a), pb = surface.evaluate(g, b);
            ASSERT_LT(glm::length(pa.P - pb.P), 1e-4f);
            ReliefCoord ca, cb;
            const SurfacePoint sa = reliefChart(pa, worldSpace(), ca);
            const SurfacePoint sb = reliefChart(pb, worldSpace(), cb);
            const LevelTransitions ta =
                levelTransitions(solid, sa, ca, eye, 500.0f, ts, DisplacementMode::Full);
            const LevelTransitions tb =
                levelTransitions(solid, sb, cb, eye, 500.0f, ts, DisplacementMode::Full);
            solidWorst = std::max(solidWorst, static_cast<double>(std::abs(ta.H[0] - tb.H[0])));
            normalWorst = std::max(
                normalWorst, static_cast<double>(glm::length(ta.frames[1].N - tb.frames[1].N)));
            const float ha = uv.levels[0].height(pa.uv), hb = uv.levels[0].height(pb.uv);
            uvWorst = std::max(uvWorst, static_cast<double>(std::abs(ha - hb)));
          }
        }
  EXPECT_EQ(edges, 24);
  EXPECT_LT(solidWorst, 1e-5);
  EXPECT_LT(normalWorst, 2e-3);
  EXPECT_GT(uvWorst, 5e-3);  // 0.03 amplitude: per-face charts break the uv relief at the edges
}

// Extremes: zero relief, points far from the origin, a huge lattice frequency: finite heights and
// normals, zero relief exactly flat.
TEST(SolidRelief, FiniteAtTheExtremes) {
  const TransitionSettings ts;
  for (float amplitude : {0.0f, 0.05f})
    for (float cells : {1e-6f, 4.0f, 1e6f})
      for (float far : {0.0f, 1e4f, 1e9f}) {
        const MaterialRelief relief = solidRelief(amplitude, cells);
        const SurfacePoint sp{Vec3(far, 0.3f, -far), Vec3(1, 0, 0), Vec3(0, 0, -1), Vec3(0, 1, 0),
                              Vec2(0.0f)};
        ReliefCoord coord;
        const SurfacePoint chart = reliefChart(sp, worldSpace(), coord);
        const LevelTransitions t = levelTransitions(relief, chart, coord, sp.P + Vec3(0, 2, 2),
                                                    500.0f, ts, DisplacementMode::Full);
        ASSERT_TRUE(std::isfinite(t.H[0])) << amplitude << " " << cells << " " << far;
        ASSERT_TRUE(isFinite(t.frames[1].N)) << amplitude << " " << cells << " " << far;
        if (amplitude == 0.0f) {
          EXPECT_EQ(t.H[0], 0.0f);
          EXPECT_LT(glm::length(t.frames[1].N - sp.N), 1e-6f);
        }
      }
}

}  // namespace
}  // namespace meso
