// Kautz et al. 2001, section 4: normals synthesized from turbulence through G and L follow the NDF.
// Chi-square tests (pbrt-v4 style): bins in (theta, phi), expected counts integrated from
// D(m) cos(theta) over each bin, bins with expected < 5 merged, alpha 0.01 with Sidak correction.
#include "meso/core/rng.h"
#include "meso/synthesis/beckmann_ndf.h"
#include "meso/synthesis/blinn_phong_ndf.h"
#include "meso/synthesis/synthesis_sampler.h"
#include "meso/synthesis/tabulated_ndf.h"
#include "support/chi_square.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <vector>

namespace meso {
namespace {

constexpr int kChiSquareTests = 5;  // the Sidak family: every chi-square test in this file
constexpr double kPi2 = 2.0 * std::numbers::pi;

// Bins: nR rings equal in sin^2(theta) up to sin(theta) = rMax, times nPhi sectors, plus one bin
// for everything beyond rMax. The projected-area density over the disk (x, y) = sin(theta) (cos
// phi, sin phi) is D itself, so a bin's probability is the integral of D r dr dphi.
struct PolarBins {
  int nR = 12, nPhi = 16;
  double rMax = 1.0;
  int count() const { return nR * nPhi + 1; }
  int index(const Vec3& m) const {
    const double r2 = static_cast<double>(m.x) * m.x + static_cast<double>(m.y) * m.y;
    if (r2 >= rMax * rMax) return nR * nPhi;
    const int a = std::min(static_cast<int>(r2 / (rMax * rMax) * nR), nR - 1);
    double phi = std::atan2(static_cast<double>(m.y), static_cast<double>(m.x));
    if (phi < 0.0) phi += kPi2;
    const int b = std::min(static_cast<int>(phi / kPi2 * nPhi), nPhi - 1);
    return a * nPhi + b;
  }
  // The integral of D r dr dphi over r^2 in [s0, s1], phi in [p0, p1] (midpoint rule in r^2 and
  // phi, dA = d(r^2) dphi / 2).
  static double mass(const Ndf& ndf, double s0, double s1, double p0, double p1, int nS, int nP) {
    double sum = 0.0;
    const double ds = (s1 - s0) / nS, dp = (p1 - p0) / nP;
    for (int i = 0; i < nS; ++i) {
      const double r = std::sqrt(s0 + (i + 0.5) * ds), z = std::sqrt(std::max(0.0, 1.0 - r * r));
      for (int j = 0; j < nP; ++j) {
        const double phi = p0 + (j + 0.5) * dp;
        sum += ndf.D(Vec3(static_cast<float>(r * std::cos(phi)),
                          static_cast<float>(r * std::sin(phi)), static_cast<float>(z)));
      }
    }
    return sum * ds * dp * 0.5;
  }
  std::vector<double> expected(const Ndf& ndf, double samples, int sub = 32) const {
    std::vector<double> e(count(), 0.0);
    const double r2 = rMax * rMax;
    for (int a = 0; a < nR; ++a)
      for (int b = 0; b < nPhi; ++b)
        e[a * nPhi + b] = samples * mass(ndf, r2 * a / nR, r2 * (a + 1) / nR, kPi2 * b / nPhi,
                                         kPi2 * (b + 1) / nPhi, sub, sub);
    // Integrated on its own rather than as 1 - the rest, whose quadrature error would dominate it.
    if (r2 < 1.0) e.back() = samples * mass(ndf, r2, 1.0, 0.0, kPi2, 4 * sub, nPhi * sub);
    return e;
  }
};

// Histogram of `samples` normals from draw(p) at independent random points p far apart.
std::vector<double> histogram(const PolarBins& bins, int samples,
                              const std::function<Vec3(Vec2)>& draw) {
  std::vector<double> counts(bins.count(), 0.0);
  Rng rng(20010815, 3);
  for (int k = 0; k < samples; ++k) {
    const Vec2 p(20000.0f * rng.uniform(), 20000.0f * rng.uniform());
    counts[bins.index(draw(p))] += 1.0;
  }
  return counts;
}

double chiSquarePValue(const std::vector<double>& observed, const std::vector<double>& expected,
                       const char* what, bool dumpOnFailure = true) {
  const testing::ChiSquareResult r = testing::chiSquareTest(observed, expected);
  const double alpha = testing::sidakAlpha(0.01, kChiSquareTests);
  std::printf("[chi-square] %-44s chi2 %9.1f dof %3d p %.4g\n", what, r.chi2, r.dof, r.pValue);
  if (r.pValue < alpha && dumpOnFailure) testing::dumpTable(observed, expected);
  return r.pValue;
}

constexpr int kSamples = 200000;

void expectFollowsNdf(const Ndf& ndf, float octaveCount, const char* what) {
  const SynthesisSampler sampler(ndf);
  PolarBins bins;
  bins.rMax = std::min(1.0f, std::max(ndf.support().x, ndf.support().y));
  const std::vector<double> expected = bins.expected(ndf, kSamples);
  const std::vector<double> observed =
      histogram(bins, kSamples, [&](Vec2 p) { return sampler.normalAtCount(p, octaveCount); });
  EXPECT_GT(chiSquarePValue(observed, expected, what), testing::sidakAlpha(0.01, kChiSquareTests))
      << what;
}

TEST(SynthesisSampler, IsotropicBeckmannChiSquare) {
  expectFollowsNdf(BeckmannNdf(0.3f), 5.0f, "beckmann(0.3), c = 5");
}

TEST(SynthesisSampler, AnisotropicBeckmannChiSquare) {
  expectFollowsNdf(BeckmannNdf(0.1f, 0.4f), 3.5f, "beckmann(0.1, 0.4), c = 3.5");
}

TEST(SynthesisSampler, BlinnPhongChiSquare) {
  expectFollowsNdf(BlinnPhongNdf(40.0f), 2.25f, "blinn-phong(40), c = 2.25");
}

// A two-lobed, asymmetric table: a conditional C(y | x) that really depends on x.
TabulatedNdf twoLobes() {
  const int n = 48;
  std::vector<float> v(static_cast<size_t>(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float x = -1.0f + (i + 0.5f) * 2.0f / n, y = -1.0f + (j + 0.5f) * 2.0f / n;
      const float a = (x - 0.3f) / 0.15f, b = (y + 0.1f) / 0.3f, c = (x + 0.25f) / 0.2f,
                  d = (y - 0.35f) / 0.1f;
      v[static_cast<size_t>(j) * n + i] =
          std::exp(-0.5f * (a * a + b * b)) + 0.6f * std::exp(-0.5f * (c * c + d * d));
    }
  return TabulatedNdf(n, n, v);
}

TEST(SynthesisSampler, TabulatedChiSquare) {
  expectFollowsNdf(twoLobes(), 6.0f, "tabulated two lobes, c = 6");
}

// The tests above have power: the same machinery rejects near misses.
TEST(SynthesisSampler, ChiSquareRejectsWrongDistributions) {
  const double alpha = testing::sidakAlpha(0.01, kChiSquareTests);
  BeckmannNdf aniso(0.1f, 0.4f), swapped(0.4f, 0.1f), slightlyRougher(0.11f, 0.44f);
  const SynthesisSampler sampler(aniso);
  PolarBins bins;
  bins.rMax = 0.9;
  const std::vector<double> observed =
      histogram(bins, kSamples, [&](Vec2 p) { return sampler.normalAtCount(p, 3.5f); });
  // The frame matters (axes swapped), and so does a 10% error in roughness.
  EXPECT_LT(
      chiSquarePValue(observed, bins.expected(swapped, kSamples), "control: axes swapped", false),
      alpha);
  EXPECT_LT(chiSquarePValue(observed, bins.expected(slightlyRougher, kSamples),
                            "control: 10% rougher", false),
            alpha);
  // Without G the turbulence is not uniform, and L then gives the wrong distribution.
  const std::vector<double> withoutG = histogram(bins, kSamples, [&](Vec2 p) {
    const Vec2 t = sampler.turbulence().evaluate(p, 3.5f);
    return sampler.table().lookup(glm::clamp(t + 0.5f, 0.0f, 1.0f));
  });
  EXPECT_LT(chiSquarePValue(withoutG, bins.expected(aniso, kSamples),
                            "control: turbulence without G", false),
            alpha);
}

}  // namespace
}  // namespace meso
