// Becker & Max 1993, eq. 4: the Blinn normal is the first-order normal of P + h n.
#include "meso/relief/blinn_normal.h"

#include <gtest/gtest.h>

#include <cmath>

namespace meso {
namespace {

using D3 = glm::dvec3;

// A curved, stretched, non-orthogonal parameterization and a height on it.
D3 P(double u, double v) {
  return {2.0 * u + 0.9 * v, 0.6 * v + 0.2 * u * v, 0.4 * u * u + 0.3 * std::sin(2 * v)};
}
double h(double u, double v) { return std::sin(3 * u + 1) * std::cos(2 * v); }
double hu(double u, double v) { return 3 * std::cos(3 * u + 1) * std::cos(2 * v); }
double hv(double u, double v) { return -2 * std::sin(3 * u + 1) * std::sin(2 * v); }

constexpr double kStep = 1e-5;
template <typename F>
D3 du(F&& f, double u, double v) {
  return (f(u + kStep, v) - f(u - kStep, v)) / (2 * kStep);
}
template <typename F>
D3 dv(F&& f, double u, double v) {
  return (f(u, v + kStep) - f(u, v - kStep)) / (2 * kStep);
}
D3 unitNormal(double u, double v) { return glm::normalize(glm::cross(du(P, u, v), dv(P, u, v))); }

// The exact normal of the displaced surface P + a h n.
D3 exactNormal(double a, double u, double v) {
  const auto displaced = [a](double s, double t) {
    return P(s, t) + a * h(s, t) * unitNormal(s, t);
  };
  return glm::normalize(glm::cross(du(displaced, u, v), dv(displaced, u, v)));
}

Vec3 f(const D3& x) { return Vec3(x); }

double blinnError(double a, double u, double v) {
  const Vec3 n = blinnNormal(f(du(P, u, v)), f(dv(P, u, v)), f(unitNormal(u, v)),
                             static_cast<float>(a * hu(u, v)), static_cast<float>(a * hv(u, v)));
  return glm::length(D3(n) - exactNormal(a, u, v));
}

// Eq. 4 as printed: the unnormalized N = P_u x P_v in the cross terms.
double literalError(double a, double u, double v) {
  const D3 Pu = du(P, u, v), Pv = dv(P, u, v), N = glm::cross(Pu, Pv);
  const D3 r = N + a * hu(u, v) * glm::cross(N, Pv) - a * hv(u, v) * glm::cross(N, Pu);
  return glm::length(glm::normalize(r) - exactNormal(a, u, v));
}

// error = O(a^2): error / a halves when a halves.
TEST(BlinnNormal, FirstOrderNormalOfTheDisplacedSurface) {
  for (const auto& [u, v] : {std::pair{0.4, 0.3}, std::pair{-0.7, 1.1}, std::pair{1.3, -0.5}}) {
    ASSERT_GT(std::abs(glm::length(glm::cross(du(P, u, v), dv(P, u, v))) - 1.0), 0.1)
        << "stretched";
    double previous = 0.0;
    for (double a : {0.04, 0.02, 0.01, 0.005}) {
      const double perA = blinnError(a, u, v) / a;
      if (previous > 0.0) {
        EXPECT_GT(perA / previous, 0.4) << u << " " << v << " a=" << a;
        EXPECT_LT(perA / previous, 0.6) << u << " " << v << " a=" << a;
      }
      previous = perA;
    }
    // The literal formula is off at first order on this stretched surface: error / a stays put.
    EXPECT_GT(literalError(0.005, u, v) / 0.005, 0.7 * literalError(0.01, u, v) / 0.01);
    EXPECT_GT(literalError(0.005, u, v), 10 * blinnError(0.005, u, v));
  }
}

// Exactly normalize(P'_u x P'_v) with P'_u = P_u + B_u n, for any B.
TEST(BlinnNormal, IsTheNormalOfTheDisplacedTangents) {
  const Vec3 Pu(1.5f, 0.2f, 0.1f), Pv(0.7f, 0.4f, -0.2f), n = glm::normalize(glm::cross(Pu, Pv));
  for (float Bu : {-30.0f, -0.3f, 0.0f, 2.0f})
    for (float Bv : {-4.0f, 0.0f, 0.6f, 25.0f}) {
      const Vec3 expected = glm::normalize(glm::cross(Pu + Bu * n, Pv + Bv * n));
      EXPECT_LT(glm::length(blinnNormal(Pu, Pv, n, Bu, Bv) - expected), 1e-5f) << Bu << " " << Bv;
      EXPECT_LT(glm::length(blinnNormal(Pu, Pv, Bu, Bv) - expected), 1e-5f);
    }
  // A mirrored parameterization (P_u x P_v = -N) still faces N.
  EXPECT_GT(glm::dot(blinnNormal(Pv, Pu, n, 0.3f, -0.2f), n), 0.0f);
}

TEST(BlinnNormal, FiniteAtTheExtremes) {
  const Vec3 Pu(1, 0, 0), Pv(0.3f, 2, 0), N(0, 0, 1);
  EXPECT_EQ(blinnNormal(Pu, Pv, N, 0.0f, 0.0f), N);  // amplitude 0
  for (float B : {1e30f, -1e30f, 3e38f, INFINITY, NAN, 1e-40f}) {
    const Vec3 n = blinnNormal(Pu, Pv, N, B, 0.5f * B);
    EXPECT_TRUE(isFinite(n)) << B;
    EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f) << B;
    EXPECT_GE(glm::dot(n, N), -1e-6f) << B;
  }
  // Huge slopes: the limit is the tangential normal, perpendicular to N.
  EXPECT_NEAR(glm::dot(blinnNormal(Pu, Pv, N, 1e30f, 0.0f), N), 0.0f, 1e-6f);
  // Degenerate frames: P_u x P_v = 0, zero or NaN N; an N whose squared length overflows falls back
  // to +z like a non-finite one.
  EXPECT_EQ(blinnNormal(Pu, Pv, Vec3(3e19f, 0, 0), 0.0f, 0.0f), Vec3(0, 0, 1));
  EXPECT_EQ(blinnNormal(Vec3(0.0f), Pv, N, 1.0f, 2.0f), N);
  EXPECT_EQ(blinnNormal(Pu, 2.0f * Pu, N, 1.0f, 2.0f), N);
  for (const Vec3& bad : {Vec3(0.0f), Vec3(NAN), Vec3(INFINITY, 0, 0)}) {
    EXPECT_TRUE(isFinite(blinnNormal(Pu, Pv, bad, 0.5f, 0.5f)));
    EXPECT_TRUE(isFinite(blinnNormal(bad, Pv, N, 0.5f, 0.5f)));
    EXPECT_TRUE(isFinite(blinnNormal(bad, bad, 0.5f, 0.5f)));
  }
}

}  // namespace
}  // namespace meso
