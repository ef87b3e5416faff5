// Becker & Max 1993, section 2.2: convergence order and continuity of the bump derivatives.
#include "meso/relief/bump_derivatives.h"
#include "meso/core/rng.h"
#include "meso/relief/height_table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace meso {
namespace {

double analytic(double x, double y) { return std::sin(2 * M_PI * x) * std::cos(2 * M_PI * y); }
Vec2 analyticGradient(Vec2 p) {
  const double x = p.x, y = p.y;
  return {static_cast<float>(2 * M_PI * std::cos(2 * M_PI * x) * std::cos(2 * M_PI * y)),
          static_cast<float>(-2 * M_PI * std::sin(2 * M_PI * x) * std::sin(2 * M_PI * y))};
}

HeightTable sampled(int n, BumpDerivativeMethod m) {
  std::vector<float> t(static_cast<size_t>(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      t[static_cast<size_t>(j) * n + i] =
          static_cast<float>(analytic((i + 0.5) / n, (j + 0.5) / n));
  return HeightTable(n, n, std::move(t), HeightTableOptions{true, m});
}

HeightTable randomTable(int w, int h, uint64_t seed, BumpDerivativeMethod m) {
  Rng rng(seed);
  std::vector<float> t(static_cast<size_t>(w) * h);
  for (float& v : t) v = rng.uniform();
  return HeightTable(w, h, std::move(t), HeightTableOptions{true, m});
}

// Largest error of the gradient (per unit of tile coordinate) over random points.
double maxGradientError(const HeightTable& table) {
  Rng rng(3);
  double worst = 0.0;
  for (int k = 0; k < 2000; ++k) {
    const Vec2 p(rng.uniform(), rng.uniform());
    worst =
        std::max(worst, static_cast<double>(glm::length(table.gradient(p) - analyticGradient(p))));
  }
  return worst;
}

// Least-squares slope of log(error) against log(h = 1 / n) over n = 16, 32, 64, 128.
double fittedOrder(BumpDerivativeMethod m) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (int n : {16, 32, 64, 128}) {
    const double x = std::log(1.0 / n), y = std::log(maxGradientError(sampled(n, m)));
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  return (4 * sxy - sx * sy) / (4 * sxx - sx * sx);
}

// Both schemes are second order on smooth heights: the quadratic B-spline derivative smooths
// (error h^2/6 f''' from the spline, h^2/8 from the linear interpolation across), and central
// differences one texel apart of bilinear lookups are the linear interpolation of second-order
// central differences at the texel centres.
TEST(BumpDerivatives, ConvergeAtSecondOrder) {
  const double quadratic = fittedOrder(BumpDerivativeMethod::Quadratic);
  const double central = fittedOrder(BumpDerivativeMethod::CentralDifference);
  EXPECT_GE(quadratic, 1.8) << quadratic;
  EXPECT_LE(quadratic, 2.3) << quadratic;
  EXPECT_GE(central, 1.8) << central;
  EXPECT_LE(central, 2.3) << central;
}

// B_u at texel coordinate x (the knots, texel centres, are the integers), in table units per texel.
double bu(const HeightTable& t, double x, double y) { return quadraticDerivatives(t, x, y).x; }
double buCentral(const HeightTable& t, double x, double y) {
  return centralDifferenceDerivatives(t, x, y).x;
}

// The Mach-band argument of section 2.2. The quadratic B_u is a C1 quadratic spline: across a knot
// its value and its slope are continuous. Central differences of bilinear lookups (epsilon = one
// texel, eq. 3) give a B_u that is continuous in value but whose slope jumps at every knot (the
// kinks of the bilinear interpolation): that jump is what shows as Mach bands.
TEST(BumpDerivatives, QuadraticIsC1AcrossTexelBoundaries) {
  const HeightTable t = randomTable(32, 32, 5, BumpDerivativeMethod::Quadratic);
  const double y = 7.37, e = 1e-7, s = 1e-3;
  double scale = 0.0;  // the size of B_u along the row
  for (int k = 0; k < 4 * 32; ++k) scale = std::max(scale, std::abs(bu(t, 0.25 * k, y)));
  double valueJumpQ = 0.0, valueJumpC = 0.0, detrendedQ = 0.0, slopeJumpQ = 0.0, slopeJumpC = 0.0;
  for (int k = 0; k < 32; ++k) {
    valueJumpQ = std::max(valueJumpQ, std::abs(bu(t, k + e, y) - bu(t, k - e, y)));
    valueJumpC = std::max(valueJumpC, std::abs(buCentral(t, k + e, y) - buCentral(t, k - e, y)));
    // Minus the smooth change over 2e (the same difference just right of the knot): what is left
    // is a jump, plus float rounding.
    detrendedQ = std::max(detrendedQ, std::abs((bu(t, k + e, y) - bu(t, k - e, y)) -
                                               (bu(t, k + 3 * e, y) - bu(t, k + e, y))));
    // One-sided slopes of B_u on both sides of the knot.
    const auto jump = [&](auto&& f) {
      return std::abs((f(t, k + s, y) - f(t, k, y)) / s - (f(t, k, y) - f(t, k - s, y)) / s);
    };
    slopeJumpQ = std::max(slopeJumpQ, jump(bu));
    slopeJumpC = std::max(slopeJumpC, jump(buCentral));
  }
  // Measured here, relative to the scale: quadratic value change 5.4e-7 (mostly the smooth change
  // over 2e), detrended 1.6e-7, slope jump 1.8e-3; central-difference slope jump 1.8.
  EXPECT_LT(valueJumpQ, 1e-6 * scale) << valueJumpQ << " vs " << scale;
  EXPECT_LT(detrendedQ, 1e-6 * scale) << detrendedQ << " vs " << scale;
  EXPECT_LT(valueJumpC, 1e-6 * scale) << "central differences one texel apart are continuous";
  // The quadratic slope changes only by its own (piecewise constant) second derivative over 2s.
  EXPECT_LT(slopeJumpQ, 1e-2 * scale) << slopeJumpQ << " vs " << scale;
  EXPECT_GT(slopeJumpC, 1e-1 * scale) << slopeJumpC << " vs " << scale;
}

TEST(BumpDerivatives, ExactForLinearRamps) {
  std::vector<float> t(16 * 16);
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i) t[j * 16 + i] = 0.25f * i + 0.5f * j;
  for (auto m : {BumpDerivativeMethod::Quadratic, BumpDerivativeMethod::CentralDifference}) {
    const HeightTable h(16, 16, t, HeightTableOptions{false, m});
    for (double x : {1.0, 3.2, 7.5, 12.999}) {
      const Vec2 g = bumpDerivatives(h, x, 6.3, m);  // away from the clamped edges
      EXPECT_NEAR(g.x, 0.25f, 1e-6f);
      EXPECT_NEAR(g.y, 0.5f, 1e-6f);
    }
    EXPECT_NEAR(h.gradient({0.41f, 0.5f}).x, 0.25f * 16, 1e-4f);  // per unit of u: times W
  }
}

// The difference form used in the lookup equals the paper's weights.
TEST(BumpDerivatives, MatchesThePapersWeights) {
  const HeightTable t = randomTable(8, 8, 11, BumpDerivativeMethod::Quadratic);
  Rng rng(2);
  for (int k = 0; k < 200; ++k) {
    const double x = 8.0 * rng.uniform(), y = 8.0 * rng.uniform();
    const int i = static_cast<int>(std::floor(x)), j = static_cast<int>(std::floor(y));
    const float du = static_cast<float>(x - i), dv = static_cast<float>(y - j);
    float w[4];
    quadraticDerivativeWeights(du, w);
    double expected = 0.0;
    for (int m = 0; m < 4; ++m)
      expected += w[m] * ((1 - dv) * t.texel(i - 1 + m, j) + dv * t.texel(i - 1 + m, j + 1));
    EXPECT_NEAR(bu(t, x, y), expected, 1e-5);
    EXPECT_NEAR(w[0] + w[1] + w[2] + w[3], 0.0f, 1e-6f);
  }
}

TEST(BumpDerivatives, FiniteEverywhere) {
  const HeightTable t = randomTable(5, 3, 1, BumpDerivativeMethod::Quadratic);  // odd, tiny sizes
  for (double x : {-1e30, -7.5, -1e-9, 0.0, 4.9999999, 1e12, 1e30, double(NAN), double(INFINITY)})
    for (auto m : {BumpDerivativeMethod::Quadratic, BumpDerivativeMethod::CentralDifference}) {
      const Vec2 g = bumpDerivatives(t, x, x, m);
      EXPECT_TRUE(std::isfinite(g.x) && std::isfinite(g.y)) << x;
    }
  const HeightTable one(1, 1, {0.5f});
  EXPECT_EQ(one.gradient({0.3f, 0.9f}), Vec2(0.0f));
  EXPECT_EQ(one.height({0.3f, 0.9f}), 0.5f);
}

}  // namespace
}  // namespace meso
