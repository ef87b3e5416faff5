// What `meso trade` writes: trade.csv, the summary of the default hybrid against displacement
// alone, and one progress line per configuration.
#pragma once

#include "meso/trade/reference_study.h"
#include "meso/trade/trade_result.h"

#include <cstddef>
#include <string>
#include <vector>

namespace meso::trade {

// trade.csv. Comment lines first: the reference's convergence, one line per level, and the Pareto
// front ("# pareto_front: NAME;NAME;..." by time) and "# default_hybrid: NAME"; then the header
// name,algorithm,D,spp,dicing_rate,seconds,peak_rss_mib,micropolygons,mean_abs_error,rmse,
// mean_intensity_error_pct,geometry_mib,peak_added_mib and one row per result (D empty for
// displacement alone).
std::string tradeCsv(const std::vector<TradeResult>& results, const ReferenceStudy& study);

// The default hybrid against the cheapest displacement-only configuration at least as accurate
// (equal rmse or better): ratios hybrid / displacement, so < 1 is the hybrid's saving; then the
// reference's verdict. Two lines starting "trade: ". Throws meso::Error without a default hybrid.
std::string tradeSummary(const std::vector<TradeResult>& results, const ReferenceStudy& study);

// "meso: trade 3/12 NAME  seconds MiB mp rmse mae mean" for stderr.
std::string progressLine(const TradeResult& r, size_t index, size_t count);

}  // namespace meso::trade
