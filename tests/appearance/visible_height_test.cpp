// The mean height of first hits on a relief level (visible_height.h) against rays marched through
// the relief itself.
#include "meso/appearance/visible_height.h"

#include "meso/appearance/material_tables.h"
#include "meso/core/rng.h"
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

}  // namespace
}  // namespace meso
