// Redistribution maps on synthetic distributions with known structure: identity at theta_V = 0,
// round trips, chi-square of mapped samples against the target slice, theta_W limits.
#include "meso/appearance/redistribution.h"

#include "meso/core/math.h"
#include "meso/core/rng.h"
#include "support/chi_square.h"

#include <gtest/gtest.h>

#include <cmath>

namespace meso {
namespace {

constexpr HistogramResolution kRes{9, 24, 16};

// Slice k: theta_N ~ a bump that narrows with k; phi weighted towards the viewer (phi = 0) more and
// more with k. `coupled` ties the theta spread to phi, so the slice is not a product distribution.
VisibleNormalHistogram syntheticHistogram(bool coupled) {
  VisibleNormalHistogram h(kRes);
  for (int k = 0; k < kRes.thetaV; ++k) {
    const float s = static_cast<float>(k) / (kRes.thetaV - 1);
    for (int i = 0; i < kRes.thetaN; ++i)
      for (int j = 0; j < kRes.phi; ++j) {
        const float t = h.thetaNCentre(i), p = h.phiCentre(j);
        const float facing = 1.0f + 0.9f * s * std::cos(p);
        const float width =
            0.35f * (1.0f - 0.5f * s) * (coupled ? (1.0f + 0.6f * s * std::cos(p)) : 1.0f);
        h.mass(k, i, j) = facing * (std::sin(t) * std::exp(-(t * t) / (width * width)) +
                                    (i == 20 ? 0.0f : 1e-4f));
      }
  }
  h.normalize();
  return h;
}

// Draws a normal from slice k: a bin by its mass, then uniform inside it in solid angle (the bin
// model of the redistribution tables: even in cos theta_N, even in phi).
NormalAngles sampleSlice(const VisibleNormalHistogram& h, int k, Rng& rng) {
  float u = rng.uniform();
  const auto s = h.slice(k);
  size_t b = 0;
  for (; b + 1 < s.size() && u >= s[b]; ++b) u -= s[b];
  const int i = static_cast<int>(b) / kRes.phi, j = static_cast<int>(b) % kRes.phi;
  const float c0 = std::cos(i * h.thetaNWidth()), c1 = std::cos((i + 1) * h.thetaNWidth());
  return {std::acos(c0 - rng.uniform() * (c0 - c1)),
          -kPi + (static_cast<float>(j) + rng.uniform()) * h.phiWidth()};
}

TEST(Redistribution, IdentityAtNormalIncidence) {
  const VisibleNormalHistogram h = syntheticHistogram(true);
  for (auto variant : {RedistributionVariant::Separable, RedistributionVariant::Conditional}) {
    const Redistribution r(h, variant);
    Rng rng(3);
    for (int n = 0; n < 2000; ++n) {
      const NormalAngles a = sampleSlice(h, 0, rng);
      const NormalAngles b = r.toVisible(0.0f, a);
      EXPECT_NEAR(b.thetaN, a.thetaN, h.thetaNWidth());
      EXPECT_NEAR(wrapPi(b.phi - a.phi), 0.0f, h.phiWidth());
    }
  }
}

TEST(Redistribution, RoundTripWithinOneBinOverAThetaSweep) {
  const VisibleNormalHistogram h = syntheticHistogram(true);
  for (auto variant : {RedistributionVariant::Separable, RedistributionVariant::Conditional}) {
    const Redistribution r(h, variant);
    Rng rng(5);
    for (float deg : {0.0f, 10.0f, 33.3f, 60.0f, 75.0f, 85.0f, 89.0f, 89.9f, 90.0f}) {
      for (int n = 0; n < 2000; ++n) {
        const NormalAngles a = sampleSlice(h, 0, rng);
        const NormalAngles back = r.toBump(radians(deg), r.toVisible(radians(deg), a));
        ASSERT_TRUE(std::isfinite(back.thetaN) && std::isfinite(back.phi));
        EXPECT_NEAR(back.thetaN, a.thetaN, h.thetaNWidth()) << deg;
        EXPECT_NEAR(wrapPi(back.phi - a.phi), 0.0f, h.phiWidth()) << deg;
      }
    }
  }
}

// Bump normals drawn from f and mapped by R_theta must follow distr[theta] (slice angles).
void expectMappedSamplesFollowSlices(const VisibleNormalHistogram& h,
                                     RedistributionVariant variant) {
  const Redistribution r(h, variant);
  const int slices[] = {2, 5, 8};  // 21.8, 54.5 and 87.1 degrees
  const double alpha = testing::sidakAlpha(0.01, 3);
  constexpr int kSamples = 200000;
  for (int k : slices) {
    Rng rng(100 + k);
    std::vector<double> observed(kRes.thetaN * kRes.phi, 0.0), expected(observed.size());
    for (int n = 0; n < kSamples; ++n) {
      const NormalAngles m = r.toVisible(h.thetaV(k), sampleSlice(h, 0, rng));
      observed[h.thetaNBin(m.thetaN) * kRes.phi + h.phiBin(m.phi)] += 1.0;
    }
    for (size_t b = 0; b < expected.size(); ++b) expected[b] = h.slice(k)[b] * kSamples;
    const testing::ChiSquareResult res = testing::chiSquareTest(observed, expected);
    EXPECT_GT(res.pValue, alpha) << "slice " << k << " chi2 " << res.chi2 << " dof " << res.dof;
    if (res.pValue <= alpha) testing::dumpTable(observed, expected);
  }
}

TEST(Redistribution, SeparableMapFollowsProductSlicesChiSquare) {
  expectMappedSamplesFollowSlices(syntheticHistogram(false), RedistributionVariant::Separable);
}

TEST(Redistribution, ConditionalMapFollowsCoupledSlicesChiSquare) {
  expectMappedSamplesFollowSlices(syntheticHistogram(true), RedistributionVariant::Conditional);
}

// The separable map only matches marginals: on a coupled distribution its joint histogram is off,
// which is why the conditional variant exists (this keeps the chi-square test honest).
TEST(Redistribution, SeparableMapMissesCoupling) {
  const VisibleNormalHistogram h = syntheticHistogram(true);
  const Redistribution r(h, RedistributionVariant::Separable);
  Rng rng(9);
  const int k = 8;
  std::vector<double> observed(kRes.thetaN * kRes.phi, 0.0), expected(observed.size());
  for (int n = 0; n < 200000; ++n) {
    const NormalAngles m = r.toVisible(h.thetaV(k), sampleSlice(h, 0, rng));
    observed[h.thetaNBin(m.thetaN) * kRes.phi + h.phiBin(m.phi)] += 1.0;
  }
  for (size_t b = 0; b < expected.size(); ++b) expected[b] = h.slice(k)[b] * 200000;
  EXPECT_LT(testing::chiSquareTest(observed, expected).pValue, 1e-6);
}

TEST(Redistribution, PartialDisplacementLimits) {
  const VisibleNormalHistogram h = syntheticHistogram(true);
  const Redistribution r(h, RedistributionVariant::Conditional);
  Rng rng(11);
  for (int n = 0; n < 500; ++n) {
    const NormalAngles a = sampleSlice(h, 0, rng);
    for (float deg : {0.0f, 45.0f, 89.9f, 90.0f}) {
      const float tv = radians(deg);
      const NormalAngles full = r.partial(tv, 1.0f, a);
      EXPECT_EQ(full.thetaN, a.thetaN);
      EXPECT_EQ(full.phi, a.phi);
      const NormalAngles none = r.partial(tv, 0.0f, a), plain = r.toVisible(tv, a);
      EXPECT_EQ(none.thetaN, plain.thetaN);
      EXPECT_EQ(none.phi, plain.phi);
      // Continuity at both ends: disp = 1e-6 is within a bin of plain redistribution, and
      // 1 - 1e-6 within a bin of the identity. (Not at exactly 90 degrees, where theta_W = 90 for
      // every disp > 0: at grazing any height occludes, and the surface has no projected area.)
      if (deg == 90.0f) continue;
      const NormalAngles tiny = r.partial(tv, 1e-6f, a), most = r.partial(tv, 1.0f - 1e-6f, a);
      EXPECT_NEAR(tiny.thetaN, plain.thetaN, h.thetaNWidth());
      EXPECT_NEAR(most.thetaN, a.thetaN, h.thetaNWidth());
      for (float d : {1e-9f, 0.3f, 0.7f}) {
        const NormalAngles m = r.partial(tv, d, a);
        ASSERT_TRUE(std::isfinite(m.thetaN) && std::isfinite(m.phi));
      }
    }
  }
}

// partial maps theta_W's slices straight to theta_V's; that is R_thetaV(R_thetaW^-1(n)) done as the
// paper writes it (two maps through the flat distribution), up to float rounding.
TEST(Redistribution, PartialIsTheCompositionOfTheTwoMaps) {
  const VisibleNormalHistogram h = syntheticHistogram(true);
  for (auto variant : {RedistributionVariant::Conditional, RedistributionVariant::Separable}) {
    const Redistribution r(h, variant);
    Rng rng(5);
    double worst = 0.0;
    for (int n = 0; n < 2000; ++n) {
      const NormalAngles a = sampleSlice(h, 0, rng);
      const float tv = radians(85.0f * rng.uniform()), d = rng.uniform();
      const NormalAngles direct = r.partial(tv, d, a);
      const NormalAngles composed = r.toVisible(tv, r.toBump(thetaW(tv, d), a));
      worst = std::max({worst, std::abs(static_cast<double>(direct.thetaN - composed.thetaN)),
                        std::abs(static_cast<double>(wrapPi(direct.phi - composed.phi)))});
    }
    EXPECT_LT(worst, 1e-3) << "variant " << static_cast<int>(variant);
  }
}

TEST(Redistribution, ThetaWFormulaAndLimits) {
  // cot(theta_V) = disp * cot(theta_W).
  const float tv = radians(60.0f);
  EXPECT_NEAR(1.0f / std::tan(tv), 0.5f / std::tan(thetaW(tv, 0.5f)), 1e-5f);
  EXPECT_EQ(thetaW(tv, 0.0f), 0.0f);
  EXPECT_NEAR(thetaW(tv, 1.0f), tv, 1e-6f);
  EXPECT_NEAR(thetaW(kPi / 2, 1e-9f), kPi / 2, 1e-6f);
  EXPECT_EQ(thetaW(kPi / 2, 0.0f), 0.0f);
  EXPECT_TRUE(std::isfinite(thetaW(0.0f, 1e-9f)));
}

}  // namespace
}  // namespace meso
