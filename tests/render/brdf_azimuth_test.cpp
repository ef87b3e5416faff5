// Becker & Max 1993, eq. (2): phi_{V-L} measured through the parameterization's tangents.
#include "meso/render/level_shading.h"

#include "meso/core/rng.h"

#include <gtest/gtest.h>

#include <cmath>

namespace meso {
namespace {

Vec3 direction(float theta, float phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// With orthonormal tangents eq. (2) is the angle between the tangent-plane projections of V and L.
TEST(Eq2Azimuth, OrthonormalTangentsGiveTheProjectedAngle) {
  Rng rng(8);
  for (int k = 0; k < 500; ++k) {
    const float phiV = 2 * kPi * rng.uniform(), phiL = 2 * kPi * rng.uniform();
    const Vec3 V = direction(0.05f + 1.4f * rng.uniform(), phiV),
               L = direction(0.05f + 1.4f * rng.uniform(), phiL);
    float expected = std::abs(phiV - phiL);
    if (expected > kPi) expected = 2 * kPi - expected;
    EXPECT_NEAR(azimuthEq2(V, L, Vec3(1, 0, 0), Vec3(0, 1, 0)), expected, 2e-3f);
    // Scaling both tangents alike changes nothing; rotating them about N changes nothing.
    EXPECT_NEAR(azimuthEq2(V, L, Vec3(3, 0, 0), Vec3(0, 3, 0)), expected, 2e-3f);
    EXPECT_NEAR(azimuthEq2(V, L, Vec3(0.6f, 0.8f, 0), Vec3(-0.8f, 0.6f, 0)), expected, 2e-3f);
  }
}

// A parameterization stretched twice along u: V along +x and L at 45 degrees in the world are
// [2a, 0] and [2b, b] in parameter space, atan(1/2) apart.
TEST(Eq2Azimuth, StretchedTangentsStretchTheAzimuth) {
  const Vec3 V = direction(0.7f, 0.0f), L = direction(0.4f, kPi / 4);
  EXPECT_NEAR(azimuthEq2(V, L, Vec3(2, 0, 0), Vec3(0, 1, 0)), std::atan(0.5f), 1e-5f);
  EXPECT_NEAR(azimuthEq2(V, L, Vec3(1, 0, 0), Vec3(0, 2, 0)), std::atan(2.0f), 1e-5f);
  // Warped (non-orthogonal) tangents: P_v leaning towards P_u.
  const float expected = std::acos(glm::dot(
      glm::normalize(Vec2(1.0f, std::cos(kPi / 3))),
      glm::normalize(Vec2(glm::dot(L, Vec3(1, 0, 0)), glm::dot(L, Vec3(0.5f, 0.8660254f, 0))))));
  EXPECT_NEAR(azimuthEq2(V, L, Vec3(1, 0, 0), Vec3(0.5f, 0.8660254f, 0)), expected, 1e-4f);
}

TEST(Eq2Azimuth, UndefinedAlongTheNormalAndForDegenerateTangents) {
  EXPECT_LT(azimuthEq2(Vec3(0, 0, 1), direction(0.5f, 1.0f), Vec3(1, 0, 0), Vec3(0, 1, 0)), 0.0f);
  EXPECT_LT(azimuthEq2(direction(0.5f, 1.0f), Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, 1, 0)), 0.0f);
  EXPECT_LT(azimuthEq2(direction(0.5f, 1.0f), direction(0.5f, 2.0f), Vec3(0.0f), Vec3(0.0f)), 0.0f);
  const float nan = std::nanf("");
  EXPECT_LT(azimuthEq2(Vec3(nan), direction(0.5f, 2.0f), Vec3(1, 0, 0), Vec3(0, 1, 0)), 0.0f);
}

}  // namespace
}  // namespace meso
