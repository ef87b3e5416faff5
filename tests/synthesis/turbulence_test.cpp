// Turbulence (Kautz et al. 2001, sections 3.3 and 5.1): smooth octave fade-in, determinism,
// bounds, independent channels; and G (section 4): G(turbulence) is uniform, G^-1 inverts G.
#include "meso/core/error.h"
#include "meso/core/rng.h"
#include "meso/synthesis/beckmann_ndf.h"
#include "meso/synthesis/synthesis_sampler.h"
#include "meso/synthesis/turbulence.h"
#include "meso/synthesis/turbulence_cdf.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace meso {
namespace {

std::vector<Vec2> randomPoints(int n, uint64_t seed, float extent = 100.0f) {
  Rng rng(seed, 1);
  std::vector<Vec2> p(n);
  for (Vec2& q : p) q = Vec2(extent * rng.uniform(), extent * rng.uniform());
  return p;
}

TEST(Turbulence, OctaveCountFollowsThePixelFootprint) {
  const Turbulence turb;  // base frequency 8, lacunarity 2, Nyquist 2 pixels
  EXPECT_FLOAT_EQ(turb.octaveCount(16.0f), 0.0f);  // octave 0's wavelength spans 2 pixels
  EXPECT_NEAR(turb.octaveCount(32.0f), 1.0f, 1e-6f);
  EXPECT_NEAR(turb.octaveCount(16.0f * std::pow(2.0f, 3.3f)), 3.3f, 1e-5f);
  EXPECT_FLOAT_EQ(turb.octaveCount(1e30f), 12.0f);  // maxOctaves
  EXPECT_FLOAT_EQ(turb.octaveCount(0.0f), 0.0f);
  EXPECT_FLOAT_EQ(turb.octaveCount(std::nanf("")), 0.0f);
  EXPECT_EQ(turb.evaluate(Vec2(0.3f, 0.7f), 0.0f), Vec2(0.0f));  // no octave: no detail
  EXPECT_FLOAT_EQ(Turbulence::octaveWeight(2.5f, 2), 0.5f);
  EXPECT_FLOAT_EQ(Turbulence::octaveWeight(2.5f, 1), 1.0f);
  EXPECT_FLOAT_EQ(Turbulence::octaveWeight(2.5f, 3), 0.0f);
}

// Sweep the footprint finely across an integer octave count: every step's change in t is at most
// 3.2 times the change in c (the C1 fade's bound), the largest step shrinks in proportion to the
// step (no jump), and the second difference shrinks like step^2 (C1: no kink).
TEST(Turbulence, OctaveFadeInIsContinuousAndSmooth) {
  const Turbulence turb;
  const std::vector<Vec2> points = randomPoints(400, 5);
  const auto ppuAt = [&](double c) { return static_cast<float>(16.0 * std::pow(2.0, c)); };
  const auto maxStep = [&](double h) {
    float largest = 0.0f, largestRatio = 0.0f;
    for (const Vec2& p : points) {
      for (double c = 2.9; c < 3.1; c += h) {
        const float c0 = turb.octaveCount(ppuAt(c)), c1 = turb.octaveCount(ppuAt(c + h));
        const Vec2 d = turb.evaluate(p, c1) - turb.evaluate(p, c0);
        const float jump = std::max(std::abs(d.x), std::abs(d.y));
        largest = std::max(largest, jump);
        largestRatio = std::max(largestRatio, jump / std::max(c1 - c0, 1e-9f));
      }
    }
    EXPECT_LE(largestRatio, 3.2f + 0.05f) << "step " << h;
    return largest;
  };
  const float coarse = maxStep(4e-3), fine = maxStep(1e-3);
  std::printf("[fade] max |dt| per step: %.3g at dc = 4e-3, %.3g at dc = 1e-3\n", coarse, fine);
  EXPECT_LT(fine, 0.4f * coarse);  // continuous: 0.25 expected
  // Second differences at the integer count: O(h^2) for a C1 fade (O(h) at a kink).
  const auto secondDifference = [&](float h) {
    float largest = 0.0f;
    for (const Vec2& p : points) {
      const Vec2 d =
          turb.evaluate(p, 3.0f + h) - 2.0f * turb.evaluate(p, 3.0f) + turb.evaluate(p, 3.0f - h);
      largest = std::max(largest, std::max(std::abs(d.x), std::abs(d.y)));
    }
    return largest;
  };
  const float d1 = secondDifference(0.04f), d2 = secondDifference(0.02f);
  std::printf("[fade] second difference at c = 3: %.3g (h = 0.04), %.3g (h = 0.02)\n", d1, d2);
  EXPECT_GT(d1 / d2, 3.0f);  // 4 for C1, 2 for a kink
}

TEST(Turbulence, SynthesizedNormalsFadeInWithoutPopping) {
  const BeckmannNdf ndf(0.3f);
  const SynthesisSampler sampler(ndf);
  const std::vector<Vec2> points = randomPoints(200, 9);
  const auto maxAngleStep = [&](double h) {
    float largest = 0.0f;
    for (const Vec2& p : points)
      for (double c = 1.95; c < 2.05; c += h) {
        const Vec3 a = sampler.normalAtCount(p, static_cast<float>(c)),
                   b = sampler.normalAtCount(p, static_cast<float>(c + h));
        largest = std::max(largest,
                           2.0f * std::asin(0.5f * glm::length(a - b)));  // acos loses 5e-4 near 1
      }
    return largest;
  };
  const float coarse = maxAngleStep(4e-3), fine = maxAngleStep(1e-3);
  std::printf("[fade] max normal change per step: %.3g deg at dc = 4e-3, %.3g deg at dc = 1e-3\n",
              degrees(coarse), degrees(fine));
  EXPECT_LT(fine, 0.45f * coarse);
  EXPECT_LT(degrees(coarse), 10.0f * 4e-3f);  // at most 10 degrees per octave of footprint
}

TEST(Turbulence, DeterministicBoundedAndIndependentChannels) {
  TurbulenceOptions o;
  o.seed = 42;
  const Turbulence a(o), b(o);
  o.seed = 43;
  const Turbulence other(o);
  double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0, differ = 0;
  const std::vector<Vec2> points = randomPoints(20000, 11, 1000.0f);
  for (const Vec2& p : points) {
    const Vec2 t = a.evaluate(p, 6.5f);
    EXPECT_EQ(t, b.evaluate(p, 6.5f));
    ASSERT_LE(std::max(std::abs(t.x), std::abs(t.y)), a.maxAbs());
    differ += t != other.evaluate(p, 6.5f);
    sx += t.x, sy += t.y, sxx += t.x * t.x, syy += t.y * t.y, sxy += t.x * t.y;
  }
  const double n = static_cast<double>(points.size());
  const double cov = sxy / n - sx / n * sy / n;
  const double corr = cov / std::sqrt((sxx / n - sx * sx / n / n) * (syy / n - sy * sy / n / n));
  EXPECT_LT(std::abs(corr), 0.03) << "r1 and r2 must be independent";
  EXPECT_GT(differ, 0.99 * n) << "the seed must matter";
  EXPECT_THROW(Turbulence(TurbulenceOptions{.lacunarity = 1.0f}), Error);
  EXPECT_THROW(Turbulence(TurbulenceOptions{.maxOctaves = 0}), Error);
}

// G maps turbulence to uniform numbers: Kolmogorov-Smirnov distance of G(t) from U(0, 1) at
// several octave counts (integer, fractional between measured rows, beyond the last row).
TEST(TurbulenceCdf, MakesTurbulenceUniform) {
  const Turbulence turb;
  const TurbulenceCdf G(turb);
  const int n = 40000;
  for (float c : {1.0f, 1.6f, 2.3f, 3.5f, 7.0f}) {
    std::vector<float> u;
    Rng rng(123, static_cast<uint64_t>(c * 100));
    for (int k = 0; k < n; ++k) {
      const Vec2 t = turb.evaluate(Vec2(30000.0f * rng.uniform(), 30000.0f * rng.uniform()), c);
      u.push_back(G.G(t.x, c));
      u.push_back(G.G(t.y, c));
    }
    std::sort(u.begin(), u.end());
    double ks = 0.0;
    for (size_t k = 0; k < u.size(); ++k)
      ks = std::max({ks, std::abs(u[k] - static_cast<double>(k) / u.size()),
                     std::abs(u[k] - static_cast<double>(k + 1) / u.size())});
    // KS critical value at alpha = 0.001: 1.95 / sqrt(N); G's own sampling error adds ~0.5 / sqrt(4
    // * 2^18).
    const double bound =
        1.95 / std::sqrt(static_cast<double>(u.size())) + 0.5 / std::sqrt(4.0 * (1 << 18));
    std::printf("[G] c = %.1f  KS distance %.4f (bound %.4f)\n", c, ks, bound);
    EXPECT_LT(ks, bound) << "c = " << c;
  }
  // Without G (t linearly mapped to [0, 1]) the same statistic fails by far.
  std::vector<float> raw;
  Rng rng(5, 5);
  for (int k = 0; k < n; ++k)
    raw.push_back(
        std::clamp(turb.evaluate(Vec2(3e4f * rng.uniform(), 3e4f * rng.uniform()), 3.0f).x + 0.5f,
                   0.0f, 1.0f));
  std::sort(raw.begin(), raw.end());
  double ks = 0.0;
  for (size_t k = 0; k < raw.size(); ++k)
    ks = std::max(ks, std::abs(raw[k] - static_cast<double>(k) / raw.size()));
  EXPECT_GT(ks, 0.05);
}

TEST(TurbulenceCdf, InverseRoundTripAndMonotone) {
  const Turbulence turb;
  const TurbulenceCdf G(turb);
  for (float c : {0.5f, 1.0f, 2.7f, 9.0f}) {
    float previous = -1.0f;
    for (int k = 0; k <= 200; ++k) {
      const float t = -0.9f + 1.8f * k / 200.0f, g = G.G(t, c);
      EXPECT_GE(g, previous);
      previous = g;
    }
    for (int k = 1; k < 1000; ++k) {
      const float u = k / 1000.0f;
      EXPECT_NEAR(G.G(G.inverse(u, c), c), u, 2e-5f) << "c " << c << " u " << u;
    }
    EXPECT_NEAR(G.G(0.0f, c), 0.5f, 0.01f);  // symmetric: the median is t = 0
    EXPECT_FLOAT_EQ(G.G(10.0f, c), 1.0f);
    EXPECT_FLOAT_EQ(G.G(-10.0f, c), 0.0f);
  }
}

}  // namespace
}  // namespace meso
