// The Pareto front of time against rmse: dominated configurations and the reference left out,
// ties in time broken by rmse, sorted by time.
#include "meso/trade/pareto_front.h"

#include <gtest/gtest.h>

namespace {

using meso::trade::Kind;
using meso::trade::TradeResult;

TradeResult result(Kind kind, double seconds, double rmse) {
  TradeResult r;
  r.config.kind = kind;
  r.seconds = seconds;
  r.errors.rmse = rmse;
  return r;
}

TEST(ParetoFront, KeepsOnlyUndominatedConfigurationsByTime) {
  const std::vector<TradeResult> results = {
      result(Kind::Reference, 10.0, 0.0),    // 0: excluded
      result(Kind::Hybrid, 1.0, 0.5),        // 1: front
      result(Kind::Displacement, 2.0, 0.6),  // 2: dominated by 1
      result(Kind::Displacement, 3.0, 0.2),  // 3: front
      result(Kind::Hybrid, 3.0, 0.1),        // 4: same time, better: front before 3
      result(Kind::Hybrid, 0.5, 0.9)};       // 5: fastest: front
  EXPECT_EQ(meso::trade::paretoFront(results), (std::vector<size_t>{5, 1, 4}));
}

TEST(ParetoFront, EmptyWithoutSweptConfigurations) {
  EXPECT_TRUE(meso::trade::paretoFront({result(Kind::Reference, 1.0, 0.0)}).empty());
}

}  // namespace
