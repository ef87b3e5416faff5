// fastAcos and fastAtan2 (core/math.h) against libm, in double, over dense sweeps and the edges.
#include "meso/core/math.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace meso {
namespace {

TEST(FastMath, AcosWithinOneMicroradianEverywhere) {
  double worst = 0.0;
  for (int k = 0; k <= 2000000; ++k) {
    const float x = -1.0f + 2.0f * static_cast<float>(k) / 2000000.0f;
    worst = std::max(worst, std::abs(static_cast<double>(fastAcos(x)) - std::acos(double(x))));
  }
  EXPECT_LT(worst, 1e-6);
  EXPECT_GT(worst, 0.0);            // a polynomial, not libm: the sweep sees its error
  EXPECT_EQ(fastAcos(1.0f), 0.0f);  // a normal facing the view is exactly theta 0
  EXPECT_NEAR(fastAcos(0.0f), kPi / 2, 2e-7);
  EXPECT_NEAR(fastAcos(-1.0f), kPi, 1e-6);
  EXPECT_EQ(fastAcos(1.5f), 0.0f);  // clamped, as the callers clamped for std::acos
  EXPECT_NEAR(fastAcos(-7.0f), kPi, 1e-6);
  EXPECT_TRUE(std::isnan(fastAcos(std::numeric_limits<float>::quiet_NaN())));
  // Monotone decreasing: the tables' bin edges keep their order.
  float previous = fastAcos(-1.0f);
  for (int k = 1; k <= 200000; ++k) {
    const float a = fastAcos(-1.0f + 2.0f * static_cast<float>(k) / 200000.0f);
    ASSERT_LE(a, previous + 1e-7f) << k;
    previous = a;
  }
}

TEST(FastMath, Atan2WithinOneMicroradianOnTheCircleAndAtScale) {
  double worst = 0.0;
  for (int k = 0; k < 1000000; ++k) {
    const double t = -M_PI + 2.0 * M_PI * (k + 0.5) / 1000000.0;
    for (const float r : {1e-20f, 1.0f, 3e4f}) {
      const float y = r * static_cast<float>(std::sin(t)), x = r * static_cast<float>(std::cos(t));
      double e = std::abs(static_cast<double>(fastAtan2(y, x)) - std::atan2(double(y), double(x)));
      e = std::min(e, 2.0 * M_PI - e);  // +-pi are the same azimuth
      worst = std::max(worst, e);
    }
  }
  EXPECT_LT(worst, 1e-6);
  EXPECT_GT(worst, 0.0);
}

TEST(FastMath, Atan2EdgesAreLibms) {
  const float inf = std::numeric_limits<float>::infinity();
  for (const float y : {0.0f, -0.0f, 1.0f, -1.0f, inf, -inf})
    for (const float x : {0.0f, -0.0f, 1.0f, -1.0f, inf, -inf})
      EXPECT_NEAR(fastAtan2(y, x), std::atan2(y, x), 1e-6f) << y << " " << x;
  EXPECT_EQ(fastAtan2(0.0f, 1.0f), 0.0f);
  EXPECT_EQ(fastAtan2(1.0f, 0.0f), kPi / 2);
  EXPECT_EQ(fastAtan2(0.0f, -1.0f), kPi);
  EXPECT_EQ(fastAtan2(-0.0f, -1.0f), -kPi);
  EXPECT_TRUE(std::isnan(fastAtan2(std::numeric_limits<float>::quiet_NaN(), 1.0f)));
  EXPECT_TRUE(std::isnan(fastAtan2(1.0f, std::numeric_limits<float>::quiet_NaN())));
}

}  // namespace
}  // namespace meso
