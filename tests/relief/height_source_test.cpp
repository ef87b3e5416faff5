#include "meso/core/error.h"
#include "meso/core/image_io.h"
#include "meso/core/rng.h"
#include "meso/relief/height_source.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace meso {
namespace {

namespace fs = std::filesystem;

float analytic(Vec2 p) { return std::sin(2 * kPi * p.x) * std::cos(2 * kPi * p.y); }
Vec2 analyticGradient(Vec2 p) {
  return {2 * kPi * std::cos(2 * kPi * p.x) * std::cos(2 * kPi * p.y), -2 * kPi * std::sin(2 * kPi * p.x) * std::sin(2 * kPi * p.y)};
}

HeightTable sampled(int n, BumpDerivativeMethod m) {
  std::vector<float> t(static_cast<size_t>(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) t[static_cast<size_t>(j) * n + i] = analytic({(i + 0.5f) / n, (j + 0.5f) / n});
  return HeightTable(n, n, std::move(t), true, m);
}

double maxGradientError(const HeightTable& table) {
  Rng rng(3);
  double worst = 0.0;
  for (int k = 0; k < 4000; ++k) {
    const Vec2 p(rng.uniform(), rng.uniform());
    worst = std::max(worst, static_cast<double>(glm::length(table.gradient(p) - analyticGradient(p))));
  }
  return worst;
}

// Least-squares slope of log(error) against log(h) over resolutions 16..128.
double fittedOrder(BumpDerivativeMethod m) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const int ns[] = {16, 32, 64, 128};
  for (int n : ns) {
    const double x = std::log(1.0 / n), y = std::log(maxGradientError(sampled(n, m)));
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  return (4 * sxy - sx * sy) / (4 * sxx - sx * sx);
}

TEST(HeightTable, DerivativesConvergeAtTheExpectedOrder) {
  const double quadratic = fittedOrder(BumpDerivativeMethod::Quadratic);
  const double central = fittedOrder(BumpDerivativeMethod::CentralDifference);
  // The B-spline derivative smooths (it approximates, not interpolates): second order. Central
  // differences of bilinear lookups: first order in the worst case (the kinks of the bilinear).
  EXPECT_GT(quadratic, 1.8) << quadratic;
  EXPECT_LT(quadratic, 2.3) << quadratic;
  EXPECT_GT(central, 0.8) << central;
}

// The Mach band argument: the quadratic B_u is C1 across texel boundaries (the derivative of a C2
// cubic spline), so its slope has no jump there; B_u from central differences of bilinear lookups is
// only C0: its slope jumps where the bilinear interpolation has kinks (at texel centres).
double slopeJump(const HeightTable& t, float x, float y, float e) {
  const float g0 = t.gradient({x, y}).x;
  const float left = (g0 - t.gradient({x - e, y}).x) / e, right = (t.gradient({x + e, y}).x - g0) / e;
  return std::abs(right - left);
}

TEST(HeightTable, QuadraticDerivativeIsC1AcrossTexelBoundaries) {
  Rng rng(5);
  std::vector<float> t(32 * 32);
  for (float& v : t) v = rng.uniform();
  HeightTable q(32, 32, t, true, BumpDerivativeMethod::Quadratic), c(32, 32, t, true, BumpDerivativeMethod::CentralDifference);
  double jumpQ = 0.0, jumpC = 0.0, slopeScale = 0.0;
  for (int k = 3; k < 29; ++k) {
    const float x = (k + 0.5f) / 32.0f, y = 0.37f;  // texel centres: the spline's knots, the bilinear kinks
    jumpQ = std::max(jumpQ, slopeJump(q, x, y, 2e-4f));
    jumpC = std::max(jumpC, slopeJump(c, x, y, 2e-4f));
    slopeScale = std::max(slopeScale, static_cast<double>(std::abs(q.gradient({x + 0.01f, y}).x - q.gradient({x, y}).x) / 0.01f));
  }
  // The quadratic slope changes only by its own continuous variation over 2e (about 1% here); the
  // central-difference slope jumps by the order of the slope itself.
  EXPECT_LT(jumpQ, 0.05 * slopeScale) << jumpQ << " vs " << slopeScale;
  EXPECT_GT(jumpC, 0.3 * slopeScale) << jumpC << " vs " << slopeScale;
  // And B_u itself is continuous to float rounding for the quadratic scheme.
  for (int k = 3; k < 29; ++k) {
    const float x = (k + 0.5f) / 32.0f;
    EXPECT_NEAR(q.gradient({x - 1e-6f, 0.37f}).x, q.gradient({x + 1e-6f, 0.37f}).x, 1e-3f * (1.0f + std::abs(q.gradient({x, 0.37f}).x)));
  }
}

TEST(HeightTable, ExactForLinearRamps) {
  std::vector<float> t(16 * 16);
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i) t[j * 16 + i] = 0.25f * i + 0.5f * j;
  const HeightTable h(16, 16, t, false);
  for (float x : {0.2f, 0.41f, 0.77f}) {
    const Vec2 g = h.gradient({x, 0.5f});
    EXPECT_NEAR(g.x, 0.25f * 16, 1e-3f);
    EXPECT_NEAR(g.y, 0.5f * 16, 1e-3f);
  }
}

TEST(FractalNoise, AnalyticGradientMatchesFiniteDifferencesAndTiles) {
  const FractalNoise n(4, 2.0f, 0.5f, 7);
  Rng rng(9);
  for (int k = 0; k < 500; ++k) {
    const Vec2 p(rng.uniform(), rng.uniform());
    const float e = 1e-3f;
    const Vec2 fd((n.height(p + Vec2(e, 0)) - n.height(p - Vec2(e, 0))) / (2 * e),
                  (n.height(p + Vec2(0, e)) - n.height(p - Vec2(0, e))) / (2 * e));
    EXPECT_NEAR(glm::length(fd - n.gradient(p)), 0.0f, 2e-2f * (1.0f + glm::length(fd)));
    EXPECT_NEAR(n.height(p), n.height(p + Vec2(1.0f, 0.0f)), 1e-4f);
    EXPECT_NEAR(n.height(p), n.height(p + Vec2(0.0f, -1.0f)), 1e-4f);
  }
  EXPECT_EQ(FractalNoise(4, 2.0f, 0.5f, 7).height({0.3f, 0.6f}), n.height({0.3f, 0.6f}));
  EXPECT_NE(FractalNoise(4, 2.0f, 0.5f, 8).height({0.3f, 0.6f}), n.height({0.3f, 0.6f}));
  EXPECT_FLOAT_EQ(n.highestFrequency(), 32.0f);
}

// To first order the Blinn normal is the normal of P + a h n: its error is O(a^2), so the error
// divided by a halves when a halves, on a curved, stretched, non-orthogonal parameterization.
TEST(BlinnNormal, MatchesTheDisplacedSurfaceToFirstOrder) {
  const auto P = [](float u, float v) { return Vec3(2.0f * u + 0.5f * v, 0.7f * v, 0.3f * u * u + 0.2f * std::sin(v)); };
  const auto h = [](float u, float v) { return std::sin(3 * u + 1) * std::cos(2 * v); };
  const float u = 0.4f, v = 0.3f, e = 1e-3f;
  const auto normalOf = [&](auto&& surf) {
    const Vec3 du = (surf(u + e, v) - surf(u - e, v)) / (2 * e), dv = (surf(u, v + e) - surf(u, v - e)) / (2 * e);
    return glm::normalize(glm::cross(du, dv));
  };
  const Vec3 n = normalOf(P);
  const Vec3 Pu = (P(u + e, v) - P(u - e, v)) / (2 * e), Pv = (P(u, v + e) - P(u, v - e)) / (2 * e);
  const auto nAt = [&](float uu, float vv) {
    const Vec3 pu = (P(uu + e, vv) - P(uu - e, vv)) / (2 * e), pv = (P(uu, vv + e) - P(uu, vv - e)) / (2 * e);
    return glm::normalize(glm::cross(pu, pv));
  };
  double previous = 0.0;
  for (float a : {0.04f, 0.02f, 0.01f}) {
    const auto displaced = [&](float uu, float vv) { return P(uu, vv) + a * h(uu, vv) * nAt(uu, vv); };
    const Vec3 exact = normalOf(displaced);
    const float Bu = a * (h(u + e, v) - h(u - e, v)) / (2 * e), Bv = a * (h(u, v + e) - h(u, v - e)) / (2 * e);
    const double err = glm::length(blinnNormal(Pu, Pv, n, Bu, Bv) - exact);
    if (previous > 0.0) {
      EXPECT_LT(err / previous, 0.3);  // O(a^2): about a quarter
    }
    previous = err;
  }
  // Degenerate frames give a finite fallback.
  const Vec3 fallback = blinnNormal(Vec3(0.0f), Vec3(0.0f, 1.0f, 0.0f), Vec3(0, 0, 1), 1e30f, NAN);
  EXPECT_TRUE(isFinite(fallback));
}

TEST(HeightTable, BadImagesAreClearErrors) {
  const fs::path dir = fs::temp_directory_path() / "meso_height_bad";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto message = [](auto&& f) {
    try {
      f();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([&] { HeightTable::load(dir / "missing.png"); }).find("missing.png: no such file"), std::string::npos);
  Image two(4, 4, {"Y", "A"});
  EXPECT_NE(message([&] { HeightTable::fromImage(two, "two.exr"); }).find("two.exr: height image must have 1 channel"), std::string::npos);
  Image empty;
  EXPECT_NE(message([&] { HeightTable::fromImage(empty, "zero.png"); }).find("zero.png: height image has zero size"), std::string::npos);
  Image ok(8, 8, {"Y"});
  writeExr(dir / "t.exr", ok);
  fs::resize_file(dir / "t.exr", fs::file_size(dir / "t.exr") / 2);
  EXPECT_NE(message([&] { HeightTable::load(dir / "t.exr"); }).find("t.exr: "), std::string::npos);
  std::ofstream(dir / "g.png") << "garbage";
  EXPECT_NE(message([&] { HeightTable::load(dir / "g.png"); }).find("g.png: "), std::string::npos);
  Image rgb(2, 1, {"R", "G", "B"});
  rgb.at(0, 0, 1) = 1.0f;
  EXPECT_NEAR(HeightTable::fromImage(rgb, "rgb.png").texel(0, 0), 0.7152f, 1e-6f);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace meso
