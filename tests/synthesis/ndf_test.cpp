// NDF contracts (Kautz et al. 2001, section 3.1): projected-area normalization, support boxes,
// finiteness at the extremes, and TabulatedNdf's input errors.
#include "meso/core/error.h"
#include "meso/synthesis/beckmann_ndf.h"
#include "meso/synthesis/blinn_phong_ndf.h"
#include "meso/synthesis/tabulated_ndf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace meso {
namespace {

Vec3 sphericalToVector(double theta, double phi) {
  return Vec3(static_cast<float>(std::sin(theta) * std::cos(phi)),
              static_cast<float>(std::sin(theta) * std::sin(phi)),
              static_cast<float>(std::cos(theta)));
}

// integral of D cos(theta) dw over the cone theta < thetaMax, midpoint rule in (theta, phi): a
// different quadrature from TabulatedNdf's own disk grid.
double projectedIntegral(const Ndf& ndf, double thetaMax, int nTheta = 1500, int nPhi = 360) {
  double sum = 0.0;
  const double dt = thetaMax / nTheta, dp = 2.0 * std::numbers::pi / nPhi;
  for (int a = 0; a < nTheta; ++a) {
    const double theta = (a + 0.5) * dt;
    double ring = 0.0;
    for (int b = 0; b < nPhi; ++b) ring += ndf.D(sphericalToVector(theta, (b + 0.5) * dp));
    sum += ring * std::cos(theta) * std::sin(theta);
  }
  return sum * dt * dp;
}

// The box's share of the mass: D integrated over the disk inside |x| < sx, |y| < sy.
double supportMass(const Ndf& ndf, int n = 800) {
  const Vec2 s = ndf.support();
  double sum = 0.0;
  const double hx = 2.0 * s.x / n, hy = 2.0 * s.y / n;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = -s.x + (i + 0.5) * hx, y = -s.y + (j + 0.5) * hy, r2 = x * x + y * y;
      if (r2 < 1.0)
        sum += ndf.D(Vec3(static_cast<float>(x), static_cast<float>(y),
                          static_cast<float>(std::sqrt(1.0 - r2))));
    }
  return sum * hx * hy;
}

double coneFor(const Ndf& ndf) {
  const Vec2 s = ndf.support();
  return std::asin(std::min(1.0, 1.02 * std::max(s.x, s.y)));
}

TEST(Ndf, BeckmannNormalizationAndSupport) {
  for (auto [ax, ay] : {std::pair{0.3f, 0.3f},
                        {0.05f, 0.05f},
                        {0.6f, 0.15f},
                        {0.1f, 0.9f},
                        {1e-4f, 1e-4f},
                        {2e-3f, 5e-2f}}) {
    BeckmannNdf ndf(ax, ay);
    EXPECT_NEAR(projectedIntegral(ndf, std::numbers::pi / 2 * (ax > 0.5f || ay > 0.5f) +
                                           coneFor(ndf) * !(ax > 0.5f || ay > 0.5f)),
                1.0, 1e-3)
        << ndf.name();
    EXPECT_GT(supportMass(ndf), 1.0 - 1e-4) << ndf.name();
  }
  // Rough surfaces put mass near grazing: integrate the whole hemisphere.
  EXPECT_NEAR(projectedIntegral(BeckmannNdf(1.5f), std::numbers::pi / 2), 1.0, 1e-3);
}

TEST(Ndf, BlinnPhongNormalizationAndSupport) {
  for (float n : {0.0f, 1.0f, 20.0f, 500.0f, 1e5f}) {
    BlinnPhongNdf ndf(n);
    EXPECT_NEAR(projectedIntegral(ndf, coneFor(ndf)), 1.0, 1e-3) << ndf.name();
    EXPECT_GT(supportMass(ndf), 1.0 - 1e-4) << ndf.name();
  }
}

TEST(Ndf, BeckmannMatchesTheGaussianSlopeDensity) {
  // Independent form: slope density p(s) = exp(-s^2 / a^2) / (pi a^2), D = p / cos^4.
  BeckmannNdf ndf(0.4f);
  const double theta = 0.5, a = 0.4, t = std::tan(theta);
  const double expected =
      std::exp(-t * t / (a * a)) / (std::numbers::pi * a * a * std::pow(std::cos(theta), 4));
  EXPECT_NEAR(ndf.D(sphericalToVector(theta, 1.1)), expected, 1e-5 * expected);
  // Anisotropy: rotating by 90 degrees swaps the axes.
  BeckmannNdf aniso(0.2f, 0.5f), swapped(0.5f, 0.2f);
  const Vec3 m = sphericalToVector(0.3, 0.4), r(-m.y, m.x, m.z);
  EXPECT_NEAR(aniso.D(m), swapped.D(r), 1e-4f * aniso.D(m));
  EXPECT_GT(aniso.D(sphericalToVector(0.3, std::numbers::pi / 2)),
            aniso.D(sphericalToVector(0.3, 0.0)));
}

TEST(Ndf, FiniteAtGrazingAndExtremeRoughness) {
  std::vector<std::unique_ptr<Ndf>> ndfs;
  for (float a : {1e-6f, 1e-4f, 0.3f, 10.0f, 1e4f, 1e6f})
    ndfs.push_back(std::make_unique<BeckmannNdf>(a));
  ndfs.push_back(std::make_unique<BeckmannNdf>(1e-4f, 1e4f));
  for (float n : {0.0f, 1.0f, 1e4f, 1e8f}) ndfs.push_back(std::make_unique<BlinnPhongNdf>(n));
  ndfs.push_back(std::make_unique<TabulatedNdf>(2, 2, std::vector<float>{1, 2, 3, 4}));
  for (const auto& ndf : ndfs) {
    for (double theta : {0.0, 1e-6, 0.3, 1.2, 1.5707, 1.57079, std::numbers::pi / 2}) {
      for (double phi : {0.0, 0.7, 2.0}) {
        const float d = ndf->D(sphericalToVector(theta, phi));
        EXPECT_TRUE(std::isfinite(d) && d >= 0.0f)
            << ndf->name() << " theta " << theta << ": " << d;
      }
    }
    EXPECT_EQ(ndf->D(Vec3(0, 0, -1)), 0.0f);
    EXPECT_EQ(ndf->D(Vec3(1, 0, 0)), 0.0f);
    const Vec2 s = ndf->support();
    EXPECT_TRUE(s.x > 0.0f && s.x <= 1.0f && s.y > 0.0f && s.y <= 1.0f) << ndf->name();
  }
}

TEST(Ndf, BadParametersThrow) {
  EXPECT_THROW(BeckmannNdf(0.0f), Error);
  EXPECT_THROW(BeckmannNdf(-1.0f), Error);
  EXPECT_THROW(BeckmannNdf(0.3f, std::numeric_limits<float>::quiet_NaN()), Error);
  EXPECT_THROW(BlinnPhongNdf(-2.0f), Error);
  EXPECT_THROW(BlinnPhongNdf{std::numeric_limits<float>::infinity()}, Error);
}

std::vector<float> gaussianGrid(int n, float sigmaX, float sigmaY, float cx = 0.0f) {
  std::vector<float> v(static_cast<size_t>(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float x = -1.0f + (i + 0.5f) * 2.0f / n - cx, y = -1.0f + (j + 0.5f) * 2.0f / n;
      v[static_cast<size_t>(j) * n + i] =
          std::exp(-0.5f * (x * x / (sigmaX * sigmaX) + y * y / (sigmaY * sigmaY)));
    }
  return v;
}

TEST(Ndf, TabulatedNormalizationAndInterpolation) {
  TabulatedNdf ndf(64, 64, gaussianGrid(64, 0.3f, 0.15f, 0.1f));
  EXPECT_NEAR(projectedIntegral(ndf, std::numbers::pi / 2), 1.0, 1e-3);
  // Flat data: the uniform density 1 / pi over the disk (the cosine-weighted hemisphere).
  TabulatedNdf flat(3, 5, std::vector<float>(15, 7.0f));
  EXPECT_NEAR(flat.D(Vec3(0.3f, -0.2f, std::sqrt(0.87f))), 1.0 / std::numbers::pi, 1e-4);
  EXPECT_NEAR(projectedIntegral(flat, std::numbers::pi / 2), 1.0, 1e-3);
  // Bilinear between cell centres: halfway between two centres is the mean.
  TabulatedNdf ramp(2, 2, {1.0f, 3.0f, 1.0f, 3.0f});
  EXPECT_NEAR(ramp.D(Vec3(0, 0, 1)) / ramp.D(Vec3(-0.5f, 0, std::sqrt(0.75f))), 2.0, 1e-5);
  // A narrow table gets a narrow support box.
  TabulatedNdf narrow(64, 64, gaussianGrid(64, 0.02f, 0.02f));
  EXPECT_LT(narrow.support().x, 0.5f);
  EXPECT_GT(supportMass(narrow), 1.0 - 1e-4);
}

TEST(Ndf, TabulatedRejectsBadData) {
  EXPECT_THROW(TabulatedNdf(1, 4, std::vector<float>(4, 1.0f)), Error);
  EXPECT_THROW(TabulatedNdf(4, 4, std::vector<float>(15, 1.0f)), Error);
  std::vector<float> v(16, 1.0f);
  v[5] = -1.0f;
  EXPECT_THROW(TabulatedNdf(4, 4, v), Error);
  v[5] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(TabulatedNdf(4, 4, v), Error);
  v[5] = std::numeric_limits<float>::infinity();
  EXPECT_THROW(TabulatedNdf(4, 4, v), Error);
  EXPECT_THROW(TabulatedNdf(4, 4, std::vector<float>(16, 0.0f)), Error);
  try {
    TabulatedNdf(4, 4, std::vector<float>(16, 0.0f));
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("zero"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace meso
