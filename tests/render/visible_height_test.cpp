// The mean height of first hits on a relief level (visible_height.h) against rays marched through
// the relief itself.
#include "meso/render/visible_height.h"

#include "meso/render/displacement.h"

#include "geometry/test_meshes.h"
#include "meso/core/rng.h"
#include "meso/render/relief_levels.h"
#include "support/plane_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace meso {
namespace {

// E[h_hit] of rays at theta from the normal on a plane whose unit of u is lengthPerU long: rays
// start above every height, fall cot(theta) world units per world unit across and stop at their
// first point below the relief (bisected), over random starts and azimuths.
struct Marched {
  double mean = 0.0, standardError = 0.0;
};

Marched marchedHitHeight(const ReliefLevel& level, float theta, float lengthPerU, int rays) {
  const float top = 2.0f * level.amplitude;
  const float fall = lengthPerU / std::tan(theta);  // per unit of u
  const float step = level.wavelength() / 16.0f;
  Rng rng(7);
  double sum = 0.0, squares = 0.0, mean = 0.0;
  for (int r = 0; r < rays; ++r) {
    const Vec2 start = Vec2(rng.uniform(), rng.uniform()) * 64.0f * level.wavelength();
    const float phi = 2.0f * kPi * rng.uniform();
    const Vec2 dir(std::cos(phi), std::sin(phi));
    mean += level.height(start) / rays;
    float lo = 0.0f, hi = 0.0f;
    for (float s = step;; s += step)
      if (top - s * fall <= level.height(start + s * dir)) {
        lo = s - step, hi = s;
        break;
      }
    for (int k = 0; k < 30; ++k) {
      const float mid = 0.5f * (lo + hi);
      (top - mid * fall <= level.height(start + mid * dir) ? hi : lo) = mid;
    }
    const double h = top - hi * fall;
    sum += h / rays;
    squares += h * h / rays;
  }
  return {sum - mean, std::sqrt(std::max(squares - sum * sum, 0.0) / rays)};
}

// How far relief moves the silhouette of a crest of radius R out (the cylinder -x^2 / (2 R), relief
// added vertically, one world unit per unit of u): horizontal rays at clearance c above the crest's
// top, blocked when the relief rises to them anywhere along them; the edge moves out by
// int (P(blocked | c) - [c < 0]) dc, over random positions along the axis.
Marched marchedCrestEdge(const ReliefLevel& level, float radius, int rays) {
  const float top = 2.0f * level.amplitude;
  const float reach = std::sqrt(2.0f * radius * 2.0f * top);  // the base is below the relief beyond
  const float step = level.wavelength() / 16.0f;
  constexpr int kClearances = 64;
  Rng rng(11);
  double sum = 0.0, squares = 0.0;
  for (int r = 0; r < rays; ++r) {
    const float y = rng.uniform() * 64.0f * level.wavelength();
    const float shift = rng.uniform() * 64.0f * level.wavelength();
    // The highest point of relief plus base along the ray's line: blocked exactly below it.
    float highest = -1e30f;
    for (float x = -reach; x <= reach; x += step)
      highest = std::max(highest, -x * x / (2.0f * radius) + level.height({shift + x, y}));
    double edge = 0.0;
    for (int k = 0; k < kClearances; ++k) {
      const float c = -top + 2.0f * top * (k + 0.5f) / kClearances;
      edge += ((c <= highest ? 1.0 : 0.0) - (c < 0.0f ? 1.0 : 0.0)) * 2.0 * top / kClearances;
    }
    sum += edge / rays;
    squares += edge * edge / rays;
  }
  return {sum, std::sqrt(std::max(squares - sum * sum, 0.0) / rays)};
}

TEST(VisibleHeight, SmithLambdaKnownValues) {
  // (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi)).
  EXPECT_NEAR(VisibleHeight::smithLambda(1.0f), 0.025133f, 2e-5f);
  EXPECT_NEAR(VisibleHeight::smithLambda(0.5f), 0.19964f, 2e-5f);
  EXPECT_LT(VisibleHeight::smithLambda(3.0f), 1e-5f);
  EXPECT_GT(VisibleHeight::smithLambda(0.0f), 1e5f);
  EXPECT_GT(VisibleHeight::smithLambda(-1.0f), 1e5f);
  EXPECT_FALSE(std::isnan(VisibleHeight::smithLambda(std::nanf(""))));
}

// Smith's uncorrelated model against the relief itself, on the terrain's stones and a relief three
// times as steep, on unit-speed and stretched (2 world units per unit of u) surfaces.
TEST(VisibleHeight, MatchesRaysMarchedThroughTheRelief) {
  for (float amplitude : {0.0375f, 0.1125f}) {
    const ReliefLevel level = makeReliefLevel(testing::noiseLevel(amplitude, 1.0f, 3));
    const VisibleHeight visible(level);
    for (float lengthPerU : {1.0f, 2.0f})
      for (float degrees : {80.0f, 85.0f, 88.0f}) {
        const float theta = radians(degrees);
        const Marched marched = marchedHitHeight(level, theta, lengthPerU, 600);
        const float model = visible.at(std::cos(theta), lengthPerU);
        EXPECT_NEAR(model, marched.mean, 4.0 * marched.standardError + 0.15 * marched.mean)
            << "amplitude " << amplitude << ", " << lengthPerU << " per u, theta " << degrees;
      }
  }
}

// A crest's silhouette moves out less than an unbounded plane's, the less the tighter the crest.
TEST(VisibleHeight, CrestsMatchRaysMarchedOverACurvedSurface) {
  const ReliefLevel level = makeReliefLevel(testing::noiseLevel(0.0375f, 1.0f, 3));
  const VisibleHeight visible(level);
  const float plane = visible.at(0.0f, 1.0f);
  float previous = 0.0f;
  for (float radius : {0.05f, 0.3f, 2.0f, 10.0f}) {
    const Marched marched = marchedCrestEdge(level, radius, 300);
    const float model = visible.at(0.0f, 1.0f, 1.0f / radius);
    EXPECT_NEAR(model, marched.mean, 4.0 * marched.standardError + 0.15 * marched.mean) << radius;
    EXPECT_GT(model, previous) << radius;
    EXPECT_LT(model, 0.7f * plane) << radius;
    previous = model;
  }
  // A crest 4 times as long in u is the same crest on a surface of half the length per unit of u.
  EXPECT_NEAR(visible.at(0.0f, 0.5f, 1.0f / 0.3f), visible.at(0.0f, 1.0f, 1.0f / 1.2f), 1e-6f);
}

// 0 seen from above, rising monotonically towards grazing views, below the highest height, and
// finite at the extremes: exactly grazing, zero relief, a degenerate parameterization.
TEST(VisibleHeight, RisesFromTheMeanPlaneTowardsGrazingViews) {
  const ReliefLevel level = makeReliefLevel(testing::noiseLevel(0.05f, 2.0f, 3));
  const VisibleHeight visible(level);
  EXPECT_EQ(visible.at(1.0f, 1.0f), 0.0f);
  float previous = 0.0f;
  for (float degrees = 30.0f; degrees <= 90.0f; degrees += 2.0f) {
    const float h = visible.at(std::cos(radians(degrees)), 1.0f);
    EXPECT_GE(h, previous) << degrees;
    previous = h;
  }
  EXPECT_GT(visible.at(0.0f, 1.0f), 0.02f);  // near the top of heights of amplitude 0.05
  EXPECT_LE(visible.at(0.0f, 1.0f),
            level.amplitude * (level.source->maxAbsHeight() + std::abs(level.midlevel)));
  EXPECT_EQ(visible.at(0.0f, 0.0f), 0.0f);
  EXPECT_TRUE(std::isfinite(visible.at(std::nanf(""), 1.0f)));
  EXPECT_TRUE(std::isfinite(visible.at(0.5f, std::numeric_limits<float>::infinity())));
  const VisibleHeight flat(makeReliefLevel(testing::noiseLevel(0.0f, 2.0f, 3)));
  EXPECT_EQ(flat.at(0.0f, 1.0f), 0.0f);
  // Relief tall for its wavelength (amplitude 5 at wavelength 1/512): the crest march is bounded,
  // wide crests take the plane's value, and nothing is infinite.
  const VisibleHeight tall(makeReliefLevel(testing::noiseLevel(5.0f, 64.0f, 3)));
  for (float curvature : {0.0f, 1e-4f, 1.0f, 1e4f}) {
    EXPECT_TRUE(std::isfinite(tall.at(0.0f, 1.0f, curvature))) << curvature;
    EXPECT_LE(tall.at(0.0f, 1.0f, curvature), tall.at(0.0f, 1.0f)) << curvature;
  }
  EXPECT_EQ(tall.at(0.0f, 1.0f, 1e-4f), tall.at(0.0f, 1.0f));
}

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

}  // namespace
}  // namespace meso
