// Schilling, Appendix A, and the (d1, d2, d3) factor of the roughness pyramid.
#include "meso/relief/schilling_phong.h"
#include "meso/core/rng.h"

#include <gtest/gtest.h>

#include <cmath>

namespace meso {
namespace {

SlopeCovariance randomCovariance(Rng& rng) {
  const float s1 = 0.05f + rng.uniform(), s2 = 0.05f + rng.uniform(), angle = 6.2f * rng.uniform();
  const float c = std::cos(angle), s = std::sin(angle);
  return {c * c * s1 * s1 + s * s * s2 * s2, c * s * (s1 * s1 - s2 * s2),
          s * s * s1 * s1 + c * c * s2 * s2};
}

TEST(RoughnessFactor, RoundTripsAndEigenvalues) {
  Rng rng(3);
  for (int k = 0; k < 100; ++k) {
    const SlopeCovariance K = randomCovariance(rng);
    const RoughnessFactor D = roughnessFactor(K);
    EXPECT_GE(D.d1, 0.0f);
    EXPECT_GE(D.d3, 0.0f);
    const SlopeCovariance back = covarianceOf(D);
    EXPECT_NEAR(back.a, K.a, 1e-5f);
    EXPECT_NEAR(back.b, K.b, 1e-5f);
    EXPECT_NEAR(back.c, K.c, 1e-5f);
    const float lambda2 =
        0.5f * (K.a + K.c) + std::sqrt(0.25f * (K.a - K.c) * (K.a - K.c) + K.b * K.b);
    EXPECT_NEAR(largestStdDev(K), std::sqrt(lambda2), 1e-5f);
  }
  const RoughnessFactor line = roughnessFactor({4.0f, 0.0f, 0.0f});
  EXPECT_EQ(line.d1, 2.0f);
  EXPECT_EQ(line.d2, 0.0f);
  EXPECT_EQ(line.d3, 0.0f);
  const RoughnessFactor bad = roughnessFactor({NAN, 1.0f, -2.0f});
  EXPECT_TRUE(std::isfinite(bad.d1) && std::isfinite(bad.d2) && std::isfinite(bad.d3));
  EXPECT_EQ(largestStdDev({9.0f, 0.0f, 1.0f}), 3.0f);
}

Vec3 halfway(float alpha, float phi) {
  return {std::sin(alpha) * std::cos(phi), std::sin(alpha) * std::sin(phi), std::cos(alpha)};
}

const Vec3 kN(0, 0, 1), kE1(1, 0, 0), kE2(0, 1, 0);

TEST(SchillingPhong, IsotropicFormIsTheAnisotropicOneWithDEqualLambdaI) {
  for (float lambda : {0.05f, 0.3f, 1.0f, 2.5f})
    for (float alpha : {0.0f, 0.1f, 0.5f, 1.2f})
      for (float phi : {0.0f, 0.7f, 2.0f}) {
        const Vec3 h = halfway(alpha, phi);
        const float c2 = std::cos(alpha) * std::cos(alpha);
        EXPECT_NEAR(modifiedCos2Alpha(kN, h, kE1, kE2, {lambda, 0.0f, lambda}),
                    modifiedCos2AlphaIsotropic(c2, lambda), 1e-5f);
      }
  // Variance 1 leaves the angle alone; more widens the highlight (alpha' < alpha), less narrows it.
  const float c2 = std::cos(0.4f) * std::cos(0.4f);
  EXPECT_NEAR(modifiedCos2AlphaIsotropic(c2, 1.0f), c2, 1e-6f);
  EXPECT_GT(modifiedCos2AlphaIsotropic(c2, 2.0f), c2);
  EXPECT_LT(modifiedCos2AlphaIsotropic(c2, 0.5f), c2);
}

// tan^2(alpha') is the Mahalanobis length s^T K^-1 s of the halfway slope s = d / cos(alpha).
TEST(SchillingPhong, AnisotropicFormIsAGaussianInSlope) {
  Rng rng(5);
  for (int k = 0; k < 50; ++k) {
    const SlopeCovariance K = randomCovariance(rng);
    const float alpha = 1.3f * rng.uniform(), phi = 6.2f * rng.uniform();
    const Vec3 h = halfway(alpha, phi);
    const float c2p = modifiedCos2Alpha(kN, h, kE1, kE2, roughnessFactor(K));
    const Vec2 s = Vec2(h.x, h.y) / h.z;
    const float det = K.a * K.c - K.b * K.b;
    const float mahalanobis = (K.c * s.x * s.x - 2 * K.b * s.x * s.y + K.a * s.y * s.y) / det;
    EXPECT_NEAR(1.0f / c2p - 1.0f, mahalanobis, 1e-3f * (1.0f + mahalanobis));
  }
  // Rough along e1 only: the highlight stretches along e1.
  const RoughnessFactor D = roughnessFactor({1.0f, 0.0f, 0.01f});
  EXPECT_GT(modifiedCos2Alpha(kN, halfway(0.3f, 0.0f), kE1, kE2, D),
            modifiedCos2Alpha(kN, halfway(0.3f, 0.5f * kPi), kE1, kE2, D));
}

TEST(SchillingPhong, TangentCovarianceOfTheNaturalSystem) {
  const SlopeCovariance K{0.5f, 0.1f, 0.2f};
  const SlopeCovariance same = tangentCovariance(K, kE1, kE2, kE1, kE2);
  EXPECT_NEAR(same.a, K.a, 1e-6f);
  EXPECT_NEAR(same.b, K.b, 1e-6f);
  EXPECT_NEAR(same.c, K.c, 1e-6f);
  // P_u twice as long: slope per unit of u is twice the tilt.
  const SlopeCovariance stretched = tangentCovariance(K, 2.0f * kE1, kE2, kE1, kE2);
  EXPECT_NEAR(stretched.a, K.a / 4, 1e-6f);
  EXPECT_NEAR(stretched.b, K.b / 2, 1e-6f);
  EXPECT_NEAR(stretched.c, K.c, 1e-6f);
}

// With K = (m / n) I the modified highlight approaches the plain (n.h)^n as m grows.
TEST(SchillingPhong, PhongCovarianceReproducesBlinnPhong) {
  const float n = 40.0f, m = 4000.0f;
  const float lambda = largestStdDev(phongCovariance(n, m));
  for (float alpha : {0.0f, 0.05f, 0.15f, 0.3f}) {
    const float c = std::cos(alpha);
    EXPECT_NEAR(schillingSpecular(modifiedCos2AlphaIsotropic(c * c, lambda), m), std::pow(c, n),
                0.02f)
        << alpha;
  }
}

TEST(SchillingPhong, FiniteAtTheExtremes) {
  const RoughnessFactor smooth{};
  EXPECT_EQ(modifiedCos2Alpha(kN, kN, kE1, kE2, smooth), 1.0f);
  EXPECT_EQ(modifiedCos2AlphaIsotropic(1.0f, 0.0f), 1.0f);
  EXPECT_NEAR(modifiedCos2Alpha(kN, halfway(0.2f, 1.0f), kE1, kE2, smooth), 0.0f, 1e-6f);
  EXPECT_EQ(modifiedCos2AlphaIsotropic(0.5f, 0.0f), 0.0f);
  EXPECT_EQ(modifiedCos2Alpha(kN, -kN, kE1, kE2, {1, 0, 1}), 0.0f);  // below the surface
  for (float x : {NAN, INFINITY, -INFINITY, 1e30f, 0.0f}) {
    const float a = modifiedCos2Alpha(kN, halfway(0.3f, 0.2f), kE1, kE2, {x, x, x});
    const float b = modifiedCos2AlphaIsotropic(x, 0.5f), c = modifiedCos2AlphaIsotropic(0.5f, x);
    const float d = schillingSpecular(x, 20.0f);
    EXPECT_TRUE(std::isfinite(a) && std::isfinite(b) && std::isfinite(c) && std::isfinite(d)) << x;
    EXPECT_TRUE(a >= 0 && a <= 1 && b >= 0 && b <= 1 && c >= 0 && c <= 1) << x;
  }
}

}  // namespace
}  // namespace meso
