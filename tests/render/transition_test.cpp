#include "meso/core/error.h"
#include "meso/geometry/limit_surface.h"
#include "meso/render/displacement.h"
#include "meso/render/transition.h"

#include "support/offsets_agree.h"
#include "support/plane_scene.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

namespace meso {
namespace {

TEST(Transition, MatchesEquationTen) {
  TransitionSettings s;
  // wavelength 0.01, p = 1000 px/rad, d = 2: nu = 5 px; (5 - 2) / (cos 60 + 0.1) = 5.
  EXPECT_NEAR(transitionParameter(0.01f, 1000.0f, 2.0f, 0.5f, s), 5.0f, 1e-5f);
  // Far away nu -> 0 and T -> -D / (cos + eps).
  EXPECT_NEAR(transitionParameter(0.01f, 1000.0f, 1e9f, 1.0f, s), -2.0f / 1.1f, 1e-5f);
}

TEST(Transition, FiniteAtTheExtremes) {
  for (float eps : {0.0f, 0.1f})
    for (float D : {0.0f, 2.0f})
      for (float d : {0.0f, 1e-9f, 1e-6f, 1.0f, 1e9f, 1e30f})
        for (float c : {-0.1f, 0.0f, 1e-7f, 0.5f, 1.0f}) {
          TransitionSettings s;
          s.eps = eps;
          s.D = D;
          const float T = transitionParameter(0.01f, 1000.0f, d, c, s);
          ASSERT_TRUE(std::isfinite(T)) << eps << " " << D << " " << d << " " << c;
          const TransitionWeights w = transitionWeights(T, s);
          ASSERT_TRUE(std::isfinite(w.brdf) && std::isfinite(w.disp));
          ASSERT_NEAR(w.brdf + w.redistribution, 1.0f, 1e-6f);
        }
}

// Weights are continuous in T, so in d and theta_V: a fine sweep never jumps by more than a small
// multiple of the step (the smoothstep's slope is at most 1.5 / (b - a)).
TEST(Transition, WeightsAreContinuousInDistanceAndAngle) {
  const TransitionSettings s;
  float prevBrdf = -1.0f, prevDisp = -1.0f, prevT = 0.0f;
  const int n = 200000;
  for (int i = 0; i <= n; ++i) {
    const float d = 0.5f + 20.0f * static_cast<float>(i) / n;
    const float T = transitionParameter(0.01f, 1000.0f, d, 0.7f, s);
    const TransitionWeights w = transitionWeights(T, s);
    if (i > 0) {
      const float dT = std::abs(T - prevT);
      EXPECT_LE(std::abs(w.brdf - prevBrdf), 1.5f / (s.e2 - s.e1) * dT + 1e-6f);
      EXPECT_LE(std::abs(w.disp - prevDisp), 1.5f / (s.e4 - s.e3) * dT + 1e-6f);
      EXPECT_LT(dT, 1e-2f);
    }
    prevBrdf = w.brdf, prevDisp = w.disp, prevT = T;
  }
  // In cos(theta_V) the slope is |nu - D| / (cos + eps)^2 <= |nu - D| / eps^2 (Lipschitz bound).
  const float nuMinusD = 0.01f * 1000.0f / 3.0f - s.D;
  const float step = 1e-4f, bound = nuMinusD / (s.eps * s.eps) * step * 1.01f;
  float prev = transitionParameter(0.01f, 1000.0f, 3.0f, 1.0f, s);
  for (int i = 1; i <= 10000; ++i) {
    const float cosV = 1.0f - static_cast<float>(i) * step;
    const float T = transitionParameter(0.01f, 1000.0f, 3.0f, cosV, s);
    EXPECT_LE(std::abs(T - prev), bound);
    prev = T;
  }
}

// A level of several octaves: the paper's T of its shortest wavelength where that is positive,
// 0 while its shortest wavelength spans fewer than D pixels and its longest more, and the T of its
// longest beyond; one octave gives eq. (10) itself.
TEST(Transition, OctavesThatSpanPixelsKeepTheTablesAway) {
  const TransitionSettings s;  // D = 2
  const float shortest = 0.01f, longest = 0.04f, p = 1000.0f, c = 0.5f;
  // d = 2: nu = 5 and 20 px: the paper's T of the shortest.
  EXPECT_EQ(transitionParameter(shortest, longest, p, 2.0f, c, s),
            transitionParameter(shortest, p, 2.0f, c, s));
  // d = 10: nu = 1 and 4 px: redistribution, where the shortest alone gives (1 - 2) / 0.6.
  EXPECT_EQ(transitionParameter(shortest, longest, p, 10.0f, c, s), 0.0f);
  EXPECT_NEAR(transitionParameter(shortest, p, 10.0f, c, s), -1.0f / 0.6f, 1e-5f);
  // d = 40: nu = 0.25 and 1 px: the T of the longest, (1 - 2) / 0.6.
  EXPECT_NEAR(transitionParameter(shortest, longest, p, 40.0f, c, s), -1.0f / 0.6f, 1e-5f);
  // One octave: eq. (10).
  for (float d : {0.5f, 2.0f, 5.0f, 10.0f, 40.0f, 1e9f})
    EXPECT_EQ(transitionParameter(shortest, shortest, p, d, c, s),
              transitionParameter(shortest, p, d, c, s));
  // Continuous and non-increasing with distance, finite at the extremes.
  float prev = transitionParameter(shortest, longest, p, 2.0f, c, s);
  for (int i = 1; i <= 100000; ++i) {
    const float d = 2.0f + 60.0f * static_cast<float>(i) / 100000.0f;
    const float T = transitionParameter(shortest, longest, p, d, c, s);
    ASSERT_LE(T, prev) << d;
    ASSERT_LT(prev - T, 1e-2f) << d;
    prev = T;
  }
  for (float d : {0.0f, 1e-9f, 1e30f})
    for (float cosV : {0.0f, 1e-7f, 1.0f})
      EXPECT_TRUE(std::isfinite(transitionParameter(shortest, longest, p, d, cosV, s)));
}

// levelTransitions reads the octaves of a noise level: three octaves of lacunarity 2 span
// wavelengths 4 : 1, and where the shortest spans half a pixel the level is redistributed, not a
// table; split into octaves (one octave each) the finest goes to its table there.
TEST(Transition, ANoiseLevelsOctavesSpanItsWavelengths) {
  const ReliefLevel whole = makeReliefLevel(testing::noiseLevel(0.01f, 1.0f, 3));
  EXPECT_FLOAT_EQ(whole.octaveSpan, 4.0f);
  EXPECT_FLOAT_EQ(whole.longestWavelength(), 4.0f * whole.wavelength());
  ReliefLevelDecl finest = testing::noiseLevel(0.01f, 1.0f, 3);
  finest.firstOctave = 2;
  const ReliefLevel octave = makeReliefLevel(finest);
  EXPECT_FLOAT_EQ(octave.octaveSpan, 1.0f);
  EXPECT_FLOAT_EQ(octave.wavelength(), whole.wavelength());
  MaterialRelief a, b;
  a.levels.push_back(makeReliefLevel(testing::noiseLevel(0.01f, 1.0f, 3)));
  b.levels.push_back(makeReliefLevel(finest));
  const SurfacePoint sp{Vec3(0.0f), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec2(0.3f, 0.4f)};
  const TransitionSettings ts;
  const float p = 500.0f;
  // Seen from above at the distance where the shortest wavelength spans half a pixel (and the
  // longest D = 2 pixels).
  const float d = whole.wavelength() * p / 0.5f;
  const Vec3 eye(0.0f, 0.0f, d);
  const LevelTransitions ta = levelTransitions(a, sp, eye, p, ts, DisplacementMode::ByTransition);
  const LevelTransitions tb = levelTransitions(b, sp, eye, p, ts, DisplacementMode::ByTransition);
  EXPECT_EQ(ta.T[0], 0.0f);
  EXPECT_EQ(ta.weights[0].brdf, 0.0f);
  EXPECT_EQ(ta.disp[0], 0.0f);
  EXPECT_NEAR(tb.T[0], (0.5f - 2.0f) / 1.1f, 1e-4f);
  EXPECT_EQ(tb.weights[0].brdf, 1.0f);
  // Eight times as far, the longest spans a quarter pixel: the table, as for one octave there.
  const LevelTransitions far =
      levelTransitions(a, sp, 8.0f * eye, p, ts, DisplacementMode::ByTransition);
  EXPECT_NEAR(far.T[0], (0.25f - 2.0f) / 1.1f, 1e-4f);
  EXPECT_EQ(far.weights[0].brdf, 1.0f);
}

TEST(Transition, RegionsFollowTheThresholds) {
  const TransitionSettings s;
  EXPECT_EQ(transitionWeights(-1.5f, s).brdf, 1.0f);
  EXPECT_EQ(transitionWeights(-1.0f, s).brdf, 1.0f);
  EXPECT_EQ(transitionWeights(-0.3f, s).brdf, 0.0f);
  EXPECT_EQ(transitionWeights(0.0f, s).redistribution, 1.0f);
  EXPECT_EQ(transitionWeights(0.3f, s).disp, 0.0f);
  EXPECT_NEAR(transitionWeights(0.65f, s).disp, 0.5f, 1e-6f);
  EXPECT_EQ(transitionWeights(1.0f, s).disp, 1.0f);
  EXPECT_EQ(transitionWeights(5.0f, s).disp, 1.0f);
}

TEST(Transition, ThresholdsInTheWrongOrderAreAnError) {
  TransitionSettings s;
  s.e2 = -2.0f;
  try {
    validateTransitionSettings(s, "render.thresholds");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "render.thresholds: thresholds must satisfy e1 < e2 < 0 < e3 < e4"),
              std::string::npos);
  }
  s = TransitionSettings{};
  s.eps = NAN;
  EXPECT_THROW(validateTransitionSettings(s, "x"), Error);
  EXPECT_NO_THROW(validateTransitionSettings(TransitionSettings{}, "x"));
}

// Three noise levels of `octaves` octaves, each four times finer: T falls from level to level.
MaterialRelief threeNoiseLevels(int octaves) {
  MaterialRelief relief;
  for (const ReliefLevelDecl& d :
       {testing::noiseLevel(0.01f, 1.0f, octaves), testing::noiseLevel(0.004f, 4.0f, octaves),
        testing::noiseLevel(0.001f, 16.0f, octaves)})
    relief.levels.push_back(makeReliefLevel(d));
  return relief;
}

// The tessellator's offsets (TransitionsFor::Offsets) skip the last level's slopes and the frame it
// raises, and read the rest as Geometry gives it: noise levels over (u, v) from near (every level
// raised) to far (none), and a solid level in its chart.
TEST(Displacement, OffsetTransitionsAreTheGeometrysWhereTheOffsetsReadThem) {
  const MaterialRelief relief = threeNoiseLevels(2);
  MaterialRelief solid;
  solid.levels.push_back(makeReliefLevel(testing::solidLevel(0.02f, 4.0f, 3, 4)));
  SolidSpace world;
  world.active = true;
  const TransitionSettings ts;
  std::array<int, 4> raised{};
  for (float distance = 0.05f; distance < 2000.0f; distance *= 1.3f)
    for (float u : {0.13f, 0.71f}) {
      const SurfacePoint sp{Vec3(u, 0.4f, 0.0f), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1),
                            Vec2(u, 0.4f)};
      const Vec3 eye(0.0f, 0.6f * distance, 0.8f * distance);
      const std::string where = "distance " + std::to_string(distance);
      const LevelTransitions geometry =
          levelTransitions(relief, sp, eye, 500.0f, ts, DisplacementMode::ByTransition);
      testing::expectOffsetsAgree(
          levelTransitions(relief, sp, ReliefCoord{sp.uv}, eye, 500.0f, ts,
                           DisplacementMode::ByTransition, {}, TransitionsFor::Offsets),
          geometry, where);
      ++raised[geometry.raised];
      ReliefCoord coord;
      const SurfacePoint chart = reliefChart(sp, world, coord);
      testing::expectOffsetsAgree(
          levelTransitions(solid, chart, coord, eye, 500.0f, ts, DisplacementMode::ByTransition, {},
                           TransitionsFor::Offsets),
          levelTransitions(solid, chart, coord, eye, 500.0f, ts, DisplacementMode::ByTransition),
          "solid, " + where);
    }
  for (int k = 0; k < 4; ++k) EXPECT_GT(raised[k], 0) << k << " levels raised";
}

// The shader's evaluation stops at the first level whose T selects the BRDF alone (the table stands
// for every finer level) and agrees with the tessellator's on every level it evaluates.
TEST(Displacement, ShadingTransitionsStopAtTheFirstTableLevel) {
  const MaterialRelief relief = threeNoiseLevels(1);
  const SurfacePoint sp{Vec3(0.0f), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec2(0.3f, 0.4f)};
  const TransitionSettings ts;
  std::array<int, 4> stops{};  // how often the shader evaluated 1, 2, 3 levels
  for (float distance = 0.25f; distance < 2000.0f; distance *= 1.5f) {
    const Vec3 eye(0.0f, 0.6f * distance, 0.8f * distance);
    const LevelTransitions all =
        levelTransitions(relief, sp, eye, 500.0f, ts, DisplacementMode::ByTransition);
    const LevelTransitions shading = levelTransitions(
        relief, sp, eye, 500.0f, ts, DisplacementMode::ByTransition, {}, TransitionsFor::Shading);
    ASSERT_EQ(all.count, 3);
    int expected = 3;
    for (int i = 0; i < 3; ++i)
      if (all.weights[i].brdf >= 1.0f) {
        expected = i + 1;
        break;
      }
    ASSERT_EQ(shading.count, expected) << distance;
    ++stops[shading.count];
    EXPECT_EQ(shading.raised, all.raised) << distance;
    for (int i = 0; i < shading.count; ++i) {
      EXPECT_EQ(shading.T[i], all.T[i]) << distance << " level " << i;
      EXPECT_EQ(shading.disp[i], all.disp[i]);
      EXPECT_EQ(shading.weights[i].brdf, all.weights[i].brdf);
      EXPECT_EQ(shading.frames[i + 1].N, all.frames[i + 1].N);
    }
  }
  // Near, every level is evaluated; far, only the coarsest (its BRDF stands for all).
  EXPECT_GT(stops[3], 0);
  EXPECT_GT(stops[1], 0);
}

// Becker & Max section 4.2: the shadow terminator is treated like the silhouette. Near relief (nu >
// D) at a light's terminator gets the silhouette's T; an overhead light changes nothing, and far
// relief (nu < D) keeps the view's own T whatever the lights.
TEST(Displacement, TheShadowTerminatorRaisesTLikeTheSilhouette) {
  MaterialRelief relief;
  relief.levels.push_back(makeReliefLevel(testing::noiseLevel(0.01f, 4.0f, 2)));
  const SurfacePoint sp{Vec3(0.0f), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec2(0.3f, 0.4f)};
  Light grazing, overhead;
  grazing.direction = glm::normalize(Vec3(-1.0f, 0.0f, -0.01f));
  overhead.direction = Vec3(0.0f, 0.0f, -1.0f);
  const TransitionSettings ts;
  for (float distance : {0.5f, 200.0f}) {
    const Vec3 eye(0.0f, 0.0f, distance);
    const float T =
        levelTransitions(relief, sp, eye, 500.0f, ts, DisplacementMode::ByTransition).T[0];
    const Light lit[] = {overhead}, terminator[] = {overhead, grazing};
    EXPECT_EQ(
        levelTransitions(relief, sp, eye, 500.0f, ts, DisplacementMode::ByTransition, lit).T[0], T);
    const float Tt =
        levelTransitions(relief, sp, eye, 500.0f, ts, DisplacementMode::ByTransition, terminator)
            .T[0];
    const float cosL = 0.01f / std::sqrt(1.0001f);
    const float silhouette = levelTransition(relief.levels[0], 1.0f, cosL, distance, 500.0f, ts);
    if (T > 0.0f) {
      EXPECT_GT(Tt, 5.0f * T) << distance;
      EXPECT_FLOAT_EQ(Tt, silhouette);
    } else {
      EXPECT_EQ(Tt, T) << distance;
    }
  }
}

// A uv compressed along one direction (a UV sphere towards its poles, a stretched chart) shortens
// the relief's wavelength along u only: along v its detail is as large on screen as on a
// unit-speed surface, and displacement draws it (rows along v). T follows the direction in which
// the relief is largest, so such a point is raised where the unit-speed one is, and the face's
// dicing bound agrees; compressed both ways, the relief is a table.
TEST(Displacement, TFollowsTheDirectionInWhichTheReliefIsLargest) {
  MaterialRelief relief;
  relief.levels.push_back(makeReliefLevel(testing::noiseLevel(0.01f, 4.0f, 2)));
  const TransitionSettings ts;
  const Vec3 eye(0.2f, 0.1f, 2.0f);
  const auto T = [&](Vec3 Pu, Vec3 Pv) {
    const SurfacePoint sp{Vec3(0.0f), Pu, Pv, Vec3(0, 0, 1), Vec2(0.3f, 0.4f)};
    return levelTransitions(relief, sp, eye, 500.0f, ts, DisplacementMode::ByTransition).T[0];
  };
  const float unit = T(Vec3(1, 0, 0), Vec3(0, 1, 0));
  ASSERT_GT(unit, ts.e4);  // raised whole on the unit-speed plane
  EXPECT_EQ(T(Vec3(0.01f, 0, 0), Vec3(0, 1, 0)), unit);
  EXPECT_EQ(T(Vec3(1, 0, 0), Vec3(0, 0.01f, 0)), unit);
  EXPECT_LT(T(Vec3(0.01f, 0, 0), Vec3(0, 0.01f, 0)), ts.e1);

  // The unit square with u running 100 times faster than v, and with both: only the second is
  // left undiced.
  for (const float vRange : {1.0f, 100.0f}) {
    ControlMesh mesh;
    mesh.positions = {Vec3(-0.5f, -0.5f, 0), Vec3(0.5f, -0.5f, 0), Vec3(0.5f, 0.5f, 0),
                      Vec3(-0.5f, 0.5f, 0)};
    mesh.faceSizes = {4};
    mesh.faceVertices = {0, 1, 2, 3};
    mesh.uvs = {Vec2(0, 0), Vec2(100, 0), Vec2(100, vRange), Vec2(0, vRange)};
    mesh.uvIndices = {0, 1, 2, 3};
    const LimitSurface surface(mesh, SubdivisionScheme::Bilinear);
    const FaceDicing dicing =
        faceDicing(surface, relief, DisplacementMode::ByTransition, ts, eye, 500.0f);
    EXPECT_EQ(dicing.needsDicing[0], vRange == 1.0f ? 1 : 0) << vRange;
  }
}

}  // namespace
}  // namespace meso
