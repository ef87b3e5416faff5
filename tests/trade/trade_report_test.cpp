// The trade summary's ratios, hybrid / displacement, from made-up results.
#include "meso/trade/trade_report.h"

#include <gtest/gtest.h>

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

}  // namespace
