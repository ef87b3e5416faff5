// The configurations of `meso trade` that no other is both faster and more accurate than.
#pragma once

#include "meso/trade/trade_result.h"

#include <cstddef>
#include <vector>

namespace meso::trade {

// Indices into `results` (the reference levels excluded) of the Pareto front of seconds against
// rmse, sorted by time.
std::vector<size_t> paretoFront(const std::vector<TradeResult>& results);

}  // namespace meso::trade
