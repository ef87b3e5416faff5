// Relief levels the hybrid draws flat (DESIGN.md section 5): their vertices lie at the mean height
// of the view's first hits on them (appearance/visible_height.h), lower on the crests of raised
// coarser levels and of the limit surface itself.
#include "meso/render/displacement.h"

#include "geometry/test_meshes.h"
#include "support/plane_scene.h"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

namespace meso {
namespace {

// The hybrid's vertices: a level drawn flat (far away, disp = 0) lies at E[h_hit] along the normal,
// a level raised completely (near, disp = 1) at its own height; the reference renderer (Full) never
// moves to E[h_hit].
TEST(VisibleHeight, FlatDrawnLevelsOfTheHybridLieAtTheMeanHitHeight) {
  MaterialRelief relief;
  relief.levels.push_back(makeReliefLevel(testing::noiseLevel(0.02f, 4.0f, 3)));
  const ReliefLevel& level = relief.levels[0];
  const VisibleHeight visible(level);
  const SurfacePoint sp{Vec3(0.0f), Vec3(2, 0, 0), Vec3(0, 2, 0), Vec3(0, 0, 1), Vec2(0.3f, 0.4f)};
  const TransitionSettings ts;
  for (float distance : {0.2f, 400.0f}) {
    const Vec3 eye = distance * glm::normalize(Vec3(1.0f, 0.0f, 0.05f));  // 87 degrees
    const ReliefDisplacement hybrid(relief, DisplacementMode::ByTransition, ts, eye, 300.0f);
    const ReliefDisplacement full(relief, DisplacementMode::Full, ts, eye, 300.0f);
    const float disp = hybrid.levels(sp).disp[0];
    const float raised = level.height(sp.uv);
    const float hit = visible.at(glm::normalize(eye).z, 2.0f);
    EXPECT_GT(hit, 1e-3f);
    EXPECT_NEAR(hybrid.offset(0, sp.uv, sp).z, disp * raised + (1.0f - disp) * hit, 1e-6f);
    EXPECT_FLOAT_EQ(full.offset(0, sp.uv, sp).z, raised);
    EXPECT_EQ(disp, distance < 1.0f ? 1.0f : 0.0f) << distance;
  }
}

// Stones drawn flat on displaced hills: on a crest of the hills (seen along the view) the stones'
// surface lies at the crest's edge height, the hills' curvature taken from second differences of
// their heights here, lower than on the unbounded plane.
TEST(VisibleHeight, FlatLevelsOnDisplacedCrestsUseTheCrestsCurvature) {
  MaterialRelief relief;
  relief.levels.push_back(makeReliefLevel(testing::noiseLevel(0.3f, 0.125f, 3)));   // hills
  relief.levels.push_back(makeReliefLevel(testing::noiseLevel(0.0375f, 1.0f, 3)));  // stones
  const ReliefLevel& hills = relief.levels[0];
  const TransitionSettings ts;
  const Vec3 eye(-20.0f, 0.0f, 1.0f);  // along +u, far: hills displaced, stones flat
  const ReliefDisplacement hybrid(relief, DisplacementMode::ByTransition, ts, eye, 300.0f);
  const VisibleHeight stones(relief.levels[1]);
  int crests = 0;
  for (float u = 0.0f; u < 4.0f && crests < 3; u += 0.01f) {
    const Vec2 uv(u, 0.37f);
    const SurfacePoint sp{Vec3(u, 0.37f, 0.0f), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), uv};
    const LevelTransitions t =
        levelTransitions(relief, sp, eye, 300.0f, ts, DisplacementMode::ByTransition);
    ASSERT_EQ(t.disp[0], 1.0f);
    ASSERT_EQ(t.disp[1], 0.0f);
    const float e = 0.01f;
    const float second =
        (hills.height(uv + Vec2(e, 0)) - 2.0f * hills.height(uv) + hills.height(uv - Vec2(e, 0))) /
        (e * e);
    const Vec3 V = glm::normalize(eye - sp.P);
    const float cosTheta = glm::dot(t.frames[1].N, V);
    if (second > -1.0f || std::abs(cosTheta) > 0.05f) continue;  // a crest, seen grazing
    ++crests;
    const float crest = stones.at(cosTheta, 1.0f, -second);
    const Vec3 expected = hills.height(uv) * t.frames[0].N + crest * t.frames[1].N;
    const Vec3 got = hybrid.offset(0, uv, sp);
    EXPECT_NEAR(got.z, expected.z, 0.1f * crest) << u;
    EXPECT_LT(crest, 0.8f * stones.at(cosTheta, 1.0f)) << u;
  }
  EXPECT_EQ(crests, 3);
}

// A level drawn flat at a smooth object's silhouette: the rays that graze it cross the relief over
// a path the object's own curvature bounds, so the level lies at the crest table's height for the
// limit surface's curvature along the view (here estimated independently, from second differences
// of limit points), below the plane's. On a plane the surface changes nothing.
TEST(VisibleHeight, FlatLevelsAtASmoothSilhouetteUseTheSurfacesCurvature) {
  MaterialRelief relief;
  relief.levels.push_back(makeReliefLevel(testing::noiseLevel(0.02f, 2.0f, 3)));
  const VisibleHeight visible(relief.levels[0]);
  const TransitionSettings ts;
  const LimitSurface torus(test::torus(24, 12, 1.0f, 0.3f), SubdivisionScheme::CatmullClark);
  const int face = 0;  // ring step 0, tube step 0: just above the outer equator
  const Vec2 c(0.5f, 0.5f);
  const SurfacePoint sp = torus.evaluate(face, c);
  // Which of s and t runs around the tube: the one whose tangent has the larger z.
  const float h = 0.05f;
  Vec2 step(h, 0.0f);
  if (std::abs(torus.evaluate(face, c + Vec2(0.0f, h)).P.z - sp.P.z) >
      std::abs(torus.evaluate(face, c + step).P.z - sp.P.z))
    step = Vec2(0.0f, h);
  const Vec3 plus = torus.evaluate(face, c + step).P, minus = torus.evaluate(face, c - step).P;
  const Vec3 tangent = (plus - minus) / (2.0f * h), second = (plus - 2.0f * sp.P + minus) / (h * h);
  const float kappa = -glm::dot(sp.N, second) / glm::dot(tangent, tangent);
  EXPECT_GT(kappa, 2.0f);  // about 1 / 0.3, the tube's (the limit surface's tube is thinner)
  EXPECT_LT(kappa, 6.0f);
  const Vec3 d = glm::normalize(tangent - glm::dot(tangent, sp.N) * sp.N);
  const Vec3 eye = sp.P + 100.0f * glm::normalize(d + 0.02f * sp.N);  // far: the level is flat
  const ReliefDisplacement curved(relief, DisplacementMode::ByTransition, ts, eye, 300.0f, {},
                                  &torus);
  const ReliefDisplacement plane(relief, DisplacementMode::ByTransition, ts, eye, 300.0f);
  ASSERT_EQ(curved.levels(sp).disp[0], 0.0f);
  const float cosTheta = glm::dot(sp.N, glm::normalize(eye - sp.P));
  const float lengthPerU = std::min(glm::length(sp.Pu), glm::length(sp.Pv));
  const float onCrest = glm::dot(curved.offset(face, c, sp), sp.N);
  const float onPlane = glm::dot(plane.offset(face, c, sp), sp.N);
  std::printf("  curvature %.3f: flat level at %.5f (plane %.5f), crest table %.5f\n", kappa,
              onCrest, onPlane, visible.at(cosTheta, lengthPerU, kappa));
  EXPECT_NEAR(onPlane, visible.at(cosTheta, lengthPerU), 1e-6f);
  EXPECT_NEAR(onCrest, visible.at(cosTheta, lengthPerU, kappa), 0.03f * onCrest);
  EXPECT_LT(onCrest, 0.9f * onPlane);
  EXPECT_GT(onCrest, 0.0f);
  // A material on curved surfaces gets the first level's crest table, on planes it skips it.
  buildVisibleHeights(relief, true);
  EXPECT_EQ(relief.visibleHeights[0].at(cosTheta, lengthPerU, kappa),
            visible.at(cosTheta, lengthPerU, kappa));
  buildVisibleHeights(relief, false);
  EXPECT_EQ(relief.visibleHeights[0].at(cosTheta, lengthPerU, kappa),
            visible.at(cosTheta, lengthPerU));
  // A plane has no curvature: the same offsets with and without its surface.
  const LimitSurface flat(test::grid(4), SubdivisionScheme::CatmullClark);
  const SurfacePoint p = flat.evaluate(5, c);
  const Vec3 far = p.P + 100.0f * glm::normalize(Vec3(1.0f, 0.3f, 0.02f));
  const ReliefDisplacement withSurface(relief, DisplacementMode::ByTransition, ts, far, 300.0f, {},
                                       &flat);
  const ReliefDisplacement without(relief, DisplacementMode::ByTransition, ts, far, 300.0f);
  EXPECT_GT(glm::dot(without.offset(5, c, p), p.N), 0.0f);
  EXPECT_NEAR(glm::dot(withSurface.offset(5, c, p), p.N), glm::dot(without.offset(5, c, p), p.N),
              1e-7f);
}

// The surface's shape operators are made per face on first use, from several threads at once: the
// offsets of a displacement that has them all stored are those of fresh ones, bit for bit, and on
// the faces near the silhouette they are not the plane's.
TEST(VisibleHeight, ShapeOperatorsMadeOnFirstUseGiveTheSameOffsets) {
  MaterialRelief relief;
  relief.levels.push_back(makeReliefLevel(testing::noiseLevel(0.02f, 2.0f, 3)));
  buildVisibleHeights(relief, true);  // shared by the displacements below
  const TransitionSettings ts;
  // 1152 faces: two chunks of stored operators (ReliefDisplacement::kShapeChunk).
  const LimitSurface torus(test::torus(48, 24, 1.0f, 0.3f), SubdivisionScheme::CatmullClark);
  const Vec3 eye(100.0f, 3.0f, 0.5f);  // far: the level is flat; the tube's sides are grazed
  const int faces = torus.numFaces();
  ASSERT_GT(faces, 1024);
  constexpr int kSide = 6;  // kSide^2 points a face
  struct Point {
    int face;
    Vec2 st;
    SurfacePoint sp;
  };
  std::vector<Point> points;
  for (int f = 0; f < faces; ++f)
    for (int j = 0; j < kSide; ++j)
      for (int i = 0; i < kSide; ++i) {
        const Vec2 st((i + 0.5f) / kSide, (j + 0.5f) / kSide);
        points.push_back({f, st, torus.evaluate(f, st)});
      }
  // Fresh: a displacement per face, which makes that face's operator at its first point.
  std::vector<Vec3> fresh, plane;
  const ReliefDisplacement flat(relief, DisplacementMode::ByTransition, ts, eye, 300.0f);
  for (int f = 0; f < faces; ++f) {
    const ReliefDisplacement first(relief, DisplacementMode::ByTransition, ts, eye, 300.0f, {},
                                   &torus);
    for (size_t k = f * kSide * kSide; k < (f + 1) * size_t(kSide * kSide); ++k) {
      fresh.push_back(first.offset(f, points[k].st, points[k].sp));
      plane.push_back(flat.offset(f, points[k].st, points[k].sp));
    }
  }
  const ReliefDisplacement shared(relief, DisplacementMode::ByTransition, ts, eye, 300.0f, {},
                                  &torus);
  const size_t n = points.size();
  for (int round = 0; round < 3; ++round) {
    std::vector<Vec3> got(n);
    tbb::parallel_for(size_t(0), n, [&](size_t i) {
      const size_t k = round % 2 ? n - 1 - i : i;
      got[k] = shared.offset(points[k].face, points[k].st, points[k].sp);
    });
    int differ = 0;
    for (size_t k = 0; k < n; ++k) differ += std::memcmp(&got[k], &fresh[k], sizeof(Vec3)) != 0;
    EXPECT_EQ(differ, 0) << "round " << round;
  }
  int curved = 0;
  for (size_t k = 0; k < n; ++k) curved += glm::length(fresh[k] - plane[k]) > 1e-6f;
  std::printf("  %d of %zu points' offsets take the tube's curvature\n", curved, n);
  EXPECT_GT(curved, 50);
}

}  // namespace
}  // namespace meso
