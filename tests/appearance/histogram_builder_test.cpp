#include "meso/appearance/histogram_builder.h"

#include "meso/core/rng.h"
#include "support/chi_square.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

namespace meso {
namespace {

struct SineRelief : PeriodicRelief {
  float a;
  explicit SineRelief(float amplitude) : a(amplitude) {}
  float height(float x, float y) const override {
    return a * std::sin(2 * kPi * x) * std::sin(2 * kPi * y);
  }
  uint64_t fingerprint() const override { return static_cast<uint64_t>(a * 1e6f); }
  Vec2 gradient(float x, float y) const override {
    return {a * 2 * kPi * std::cos(2 * kPi * x) * std::sin(2 * kPi * y),
            a * 2 * kPi * std::sin(2 * kPi * x) * std::cos(2 * kPi * y)};
  }
};

HistogramSettings smallSettings() {
  HistogramSettings s;
  s.resolution = {6, 16, 16};
  s.azimuths = 16;
  s.raysPerView = 1500;
  s.meshResolution = 96;
  return s;
}

TEST(HistogramBuilder, ZeroReliefPutsAllMassInTheFirstThetaBin) {
  const VisibleNormalHistogram h = buildVisibleNormalHistogram(SineRelief(0.0f), smallSettings());
  for (int k = 0; k < 6; ++k) {
    double first = 0.0, total = 0.0;
    for (int i = 0; i < 16; ++i)
      for (int j = 0; j < 16; ++j) {
        total += h.mass(k, i, j);
        if (i == 0) first += h.mass(k, i, j);
      }
    EXPECT_NEAR(total, 1.0, 1e-5);
    EXPECT_NEAR(first, 1.0, 1e-5);
    const Vec3 n = h.meanNormal(k, 0, h.phiBin(0.0f));
    EXPECT_NEAR(n.z, 1.0f, 1e-6f);
  }
}

// At theta_V = 0 nothing is occluded: the histogram is the distribution of Blinn normals over the
// tile's area (sampled independently here), by chi-square.
TEST(HistogramBuilder, NormalIncidenceIsTheBumpDistribution) {
  const SineRelief relief(0.08f);
  const HistogramSettings s = smallSettings();
  const VisibleNormalHistogram h = buildVisibleNormalHistogram(relief, s);
  const int total = s.azimuths * s.raysPerView;
  std::vector<double> expected(16 * 16, 0.0), observed(16 * 16);
  Rng rng(77);
  const int n = 400000;
  for (int i = 0; i < n; ++i) {
    const Vec2 g = relief.gradient(rng.uniform(), rng.uniform());
    const float phiV = 2 * kPi * rng.uniform();
    const Vec3 m = glm::normalize(Vec3(-g.x, -g.y, 1.0f));
    const NormalAngles a = anglesOf(m);
    expected[h.thetaNBin(a.thetaN) * 16 + h.phiBin(a.phi - phiV)] += static_cast<double>(total) / n;
  }
  for (int b = 0; b < 256; ++b) observed[b] = h.slice(0)[b] * total;
  const auto res = testing::chiSquareTest(observed, expected);
  EXPECT_GT(res.pValue, 0.01) << res.chi2 << " dof " << res.dof;
}

// Occlusion hides normals that face away from the eye: the mean visible normal leans towards the
// viewer (+x in the view-aligned frame) more and more as theta_V grows.
TEST(HistogramBuilder, VisibleNormalsLeanTowardsTheViewer) {
  const VisibleNormalHistogram h = buildVisibleNormalHistogram(SineRelief(0.12f), smallSettings());
  float previous = -1.0f;
  for (int k = 0; k < 6; ++k) {
    Vec3 mean(0.0f);
    for (int i = 0; i < 16; ++i)
      for (int j = 0; j < 16; ++j) mean += h.mass(k, i, j) * h.meanNormal(k, i, j);
    if (k == 0) {
      EXPECT_NEAR(mean.x, 0.0f, 0.01f);
    }
    EXPECT_GT(mean.x, previous);
    previous = mean.x;
  }
  EXPECT_GT(previous, 0.2f);
}

TEST(HistogramBuilder, SameBitsForAnyThreadCount) {
  const SineRelief relief(0.1f);
  auto build = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return buildVisibleNormalHistogram(relief, smallSettings());
  };
  const VisibleNormalHistogram a = build(1), b = build(2);
  for (int k = 0; k < 6; ++k)
    for (size_t i = 0; i < a.slice(k).size(); ++i) ASSERT_EQ(a.slice(k)[i], b.slice(k)[i]);
}

}  // namespace
}  // namespace meso
