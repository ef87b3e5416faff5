#include "meso/core/error.h"
#include "meso/render/transition.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace meso
