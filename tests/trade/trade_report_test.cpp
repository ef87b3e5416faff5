// The trade summary's ratios, hybrid / displacement, from made-up results.
#include "meso/trade/trade_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace {

using meso::trade::Kind;
using meso::trade::ReferenceStudy;
using meso::trade::TradeResult;

TradeResult result(Kind kind, double seconds, double rmse, double peakMib, double addedMib) {
  TradeResult r;
  r.config.name = kind == Kind::Hybrid ? "hybrid" : "displacement";
  r.config.kind = kind;
  r.config.defaultHybrid = kind == Kind::Hybrid;
  r.config.spp = 4;
  r.seconds = seconds;
  r.errors.rmse = rmse;
  r.peakRssMib = peakMib;
  r.addedMib = addedMib;
  r.geometryMib = kind == Kind::Hybrid ? 10.0 : 40.0;
  r.micropolygons = kind == Kind::Hybrid ? 1000 : 4000;
  return r;
}

std::string summary(double displacementAddedMib) {
  ReferenceStudy study;
  study.levels.resize(1);
  study.stop = "no refinement asked for";
  const std::vector<TradeResult> results = {
      result(Kind::Hybrid, 1.0, 0.010, 300.0, 50.0),
      result(Kind::Displacement, 3.0, 0.009, 200.0, displacementAddedMib)};
  return meso::trade::tradeSummary(results, study);
}

TEST(TradeSummary, RatiosAreHybridOverDisplacement) {
  const std::string s = summary(25.0);
  EXPECT_NE(s.find("speedup 3.00x"), std::string::npos) << s;
  EXPECT_NE(s.find("time 0.333x, peak memory 1.5x (2x of what each added above the process's "
                   "baseline), geometry memory 0.25x, micropolygons 0.25x, spp 1x"),
            std::string::npos)
      << s;
}

// Displacement's peak did not rise above its start (seen under ASan): that ratio says n/a, never
// "infx"; the others are unchanged.
TEST(TradeSummary, NothingAddedByDisplacementIsNotAnInfiniteRatio) {
  const std::string s = summary(0.0);
  EXPECT_EQ(s.find("inf"), std::string::npos) << s;
  EXPECT_NE(s.find("peak memory 1.5x (n/a of what each added above the process's baseline)"),
            std::string::npos)
      << s;
}

// One displacement-only configuration of a series (dicing rate, relief samples) at `spp`.
TradeResult displacement(float dicingRate, int spp, double seconds, double rmse) {
  TradeResult r = result(Kind::Displacement, seconds, rmse, 200.0, 20.0);
  r.config.dicingRate = dicingRate;
  r.config.reliefSamples = 0.0f;
  r.config.spp = spp;
  return r;
}

// rmse 0.04 at 1 spp and 0.02 at 4 spp is rmse = 0.04 spp^-1/2; 1 s and 2.5 s is 0.5 + 0.5 spp.
// 0.04 / sqrt(2) is reached at exactly 2 spp, in 1.5 s.
TEST(TradeInterpolation, KnownPowerLawAndLinearTime) {
  const std::vector<TradeResult> results = {displacement(1.0f, 1, 1.0, 0.04),
                                            displacement(1.0f, 4, 2.5, 0.02),
                                            displacement(1.0f, 16, 8.5, 0.01)};
  const auto i = meso::trade::interpolatedAsAccurate(results, 0.04 / std::sqrt(2.0));
  ASSERT_TRUE(i.has_value());
  EXPECT_EQ(i->fewer, &results[0]);
  EXPECT_EQ(i->more, &results[1]);
  EXPECT_NEAR(i->spp, 2.0, 1e-9);
  EXPECT_NEAR(i->seconds, 1.5, 1e-9);
  // Between 4 and 16 spp: 0.01 * sqrt(2) at 8 spp, 2.5 + 4 * 0.5 = 4.5 s.
  const auto j = meso::trade::interpolatedAsAccurate(results, 0.01 * std::sqrt(2.0));
  ASSERT_TRUE(j.has_value());
  EXPECT_NEAR(j->spp, 8.0, 1e-9);
  EXPECT_NEAR(j->seconds, 4.5, 1e-9);
}

// Only neighbours in spp of one series are paired: a cheap 1-spp point of another dicing rate and
// the 16-spp point of this one bracket the target but are not one series, and the 1-16 pair of a
// series with a 4-spp point between is not used either. The cheapest bracketing series wins.
TEST(TradeInterpolation, PairsNeighboursOfOneSeriesAndTakesTheCheapest) {
  const std::vector<TradeResult> results = {
      displacement(2.0f, 1, 0.2, 0.05),  // 2 px never reaches 0.015
      displacement(2.0f, 4, 0.5, 0.03),  displacement(1.0f, 1, 1.0, 0.04),
      displacement(1.0f, 4, 2.5, 0.02),  displacement(1.0f, 16, 8.5, 0.01),
      displacement(0.5f, 4, 6.0, 0.016), displacement(0.5f, 16, 7.0, 0.008)};
  const auto i = meso::trade::interpolatedAsAccurate(results, 0.015);
  ASSERT_TRUE(i.has_value());
  // 1 px: 0.015 between 4 and 16 spp at 4 * 4^(log(0.75) / log(0.5)) = 7.11 spp, 4.06 s; 0.5 px:
  // 4 * 4^(log(0.9375) / log(0.5)) = 4.55 spp, 6.05 s. 1 px is cheaper.
  EXPECT_EQ(i->fewer, &results[3]);
  EXPECT_EQ(i->more, &results[4]);
  EXPECT_NEAR(i->spp, 4.0 * std::pow(4.0, std::log(0.75) / std::log(0.5)), 1e-9);
  EXPECT_NEAR(i->seconds, 2.5 + 0.5 * (i->spp - 4.0), 1e-9);
  // Nothing brackets an rmse below every series' last point or above every first one.
  EXPECT_FALSE(meso::trade::interpolatedAsAccurate(results, 0.005).has_value());
  EXPECT_FALSE(meso::trade::interpolatedAsAccurate(results, 0.06).has_value());
}

// The summary names the interpolated point when it is cheaper than the swept configuration that
// is as accurate, with its speedup; the swept comparison stays as it was.
TEST(TradeSummary, InterpolatedEqualRmseBetweenSweptSpp) {
  ReferenceStudy study;
  study.levels.resize(1);
  study.stop = "no refinement asked for";
  TradeResult h = result(Kind::Hybrid, 2.0, 0.04 / std::sqrt(2.0), 300.0, 50.0);
  const std::vector<TradeResult> results = {h, displacement(1.0f, 1, 1.0, 0.04),
                                            displacement(1.0f, 4, 2.5, 0.02)};
  const std::string s = meso::trade::tradeSummary(results, study);
  EXPECT_NE(s.find("4 spp) 2.5 s, rmse 0.02, worst band +0%: speedup 1.25x; hybrid"),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("interpolated between the swept spp: displacement-only (dicing 1 px, relief "
                   "samples 0) reaches that rmse at about 2 spp (1 spp: 0.04, 4 spp: 0.02) in "
                   "about 1.5 s: speedup 0.75x (the hybrid is slower)"),
            std::string::npos)
      << s;
  // Where the swept configuration is itself at the hybrid's rmse, nothing is interpolated.
  h.errors.rmse = 0.02;
  const std::string t = meso::trade::tradeSummary({h, results[1], results[2]}, study);
  EXPECT_EQ(t.find("interpolated"), std::string::npos) << t;
}

// As consistent and as detailed: the cheaper displacement configuration keeps every band's mean
// but has half the reference's local contrast, so the comparison takes the dearer one whose
// contrast is within 10%.
TEST(TradeSummary, AsDetailedPassesOverDisplacementThatErasesTexture) {
  ReferenceStudy study;
  study.levels.resize(1);
  study.stop = "no refinement asked for";
  TradeResult h = result(Kind::Hybrid, 1.0, 0.010, 300.0, 50.0);
  h.errors.worstContrastRatio = 0.97;
  TradeResult flat = result(Kind::Displacement, 2.0, 0.009, 200.0, 20.0);
  flat.errors.worstContrastRatio = 0.5;
  TradeResult detailed = result(Kind::Displacement, 4.0, 0.009, 200.0, 20.0);
  detailed.errors.worstContrastRatio = 1.04;
  const std::string s = meso::trade::tradeSummary({h, flat, detailed}, study);
  EXPECT_NE(s.find("worst band +0%, worst contrast ratio 0.97;"), std::string::npos) << s;
  EXPECT_NE(s.find("4 spp) 2 s, rmse 0.009, worst band +0%, worst contrast ratio 0.5: speedup "
                   "2.00x"),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("trade: as consistent and as detailed too (every depth band's mean within 0.5% "
                   "of the reference's, its local contrast within 10% where the reference shows "
                   "relief): cheapest displacement-only as accurate (dicing 1 px, relief samples "
                   "-1, 4 spp) 4 s, rmse 0.009, worst band +0%, worst contrast ratio 1.04: speedup "
                   "4.00x"),
            std::string::npos)
      << s;
  EXPECT_EQ(s.find("NOT as detailed"), std::string::npos) << s;
  // A hybrid that erases texture itself is said to, and widens the tolerance to its own ratio.
  h.errors.worstContrastRatio = 0.45;
  const std::string t = meso::trade::tradeSummary({h, flat, detailed}, study);
  EXPECT_NE(t.find("worst contrast ratio 0.45 (NOT as detailed as the reference)"),
            std::string::npos)
      << t;
  EXPECT_NE(t.find("its local contrast within 55% where"), std::string::npos) << t;
}

// The third line names the fastest hybrid that meets the strict criterion (every band within
// 0.5%, contrast within 10%), whichever D it has, and passes over faster ones that miss either.
TEST(TradeSummary, CheapestHybridWithinTheCriterionIsNamed) {
  ReferenceStudy study;
  study.levels.resize(1);
  study.stop = "no refinement asked for";
  const auto hybrid = [](float D, double seconds, double bandPct, double contrast) {
    TradeResult r = result(Kind::Hybrid, seconds, 0.02, 300.0, 50.0);
    r.config.D = D;
    r.config.dicingRate = 1.0f;
    r.config.defaultHybrid = false;
    r.errors.worstBandPct = bandPct;
    r.errors.worstContrastRatio = contrast;
    return r;
  };
  TradeResult h = hybrid(2.0f, 1.0, 0.3, 0.98);
  h.config.defaultHybrid = true;
  const TradeResult d8 = hybrid(8.0f, 0.6, -0.2, 1.02);
  TradeResult d4 = hybrid(4.0f, 0.5, 0.6, 1.0);  // a band 0.6% off
  d4.micropolygons = 500;
  const TradeResult d14 = hybrid(14.0f, 0.4, 0.1, 0.85);  // 15% of the contrast lost
  const TradeResult disp = result(Kind::Displacement, 3.0, 0.01, 200.0, 20.0);
  const std::string s = meso::trade::tradeSummary({h, d8, d4, d14, disp}, study);
  EXPECT_NE(s.find("\ntrade: cheapest hybrid swept within 0.5% of the reference in every depth "
                   "band and 10% in local contrast: D 8, 1 px, 4 spp: 0.6 s (0.6x the default "
                   "hybrid's time), 1000 micropolygons (1x), peak 300.0 MiB, worst band -0.2%, "
                   "worst contrast ratio 1.02\n"),
            std::string::npos)
      << s;
  // Only the default meets it; then none does (the default is 0.51% off).
  EXPECT_NE(meso::trade::tradeSummary({h, d4, d14, disp}, study)
                .find("local contrast: the default hybrid\n"),
            std::string::npos);
  h.errors.worstBandPct = -0.51;
  EXPECT_NE(meso::trade::tradeSummary({h, d4, d14, disp}, study).find("local contrast: none\n"),
            std::string::npos);
}

}  // namespace
