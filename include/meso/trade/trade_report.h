// What `meso trade` writes: trade.csv, the summary of the default hybrid against displacement
// alone, and one progress line per configuration.
#pragma once

#include "meso/trade/reference_study.h"
#include "meso/trade/trade_result.h"

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace meso::trade {

// trade.csv. Comment lines first: the reference's convergence, one line per level, and the Pareto
// front ("# pareto_front: NAME;NAME;..." by time) and "# default_hybrid: NAME"; then the header
// name,algorithm,D,spp,dicing_rate,relief_samples,seconds,peak_rss_mib,micropolygons,
// mean_abs_error,rmse,mean_intensity_error_pct,geometry_mib,peak_added_mib,worst_band_error_pct,
// worst_contrast_ratio and one row per result (D empty for displacement alone, the contrast ratio
// empty where no depth band shows relief).
std::string tradeCsv(const std::vector<TradeResult>& results, const ReferenceStudy& study);

// The default hybrid against the cheapest displacement-only configuration at least as accurate
// (equal rmse or better): ratios hybrid / displacement, so < 1 is the hybrid's saving, and the
// speedup against interpolatedAsAccurate where that is cheaper than every swept configuration; on
// a second line the same against the cheapest one as consistent and as detailed too (no depth
// band's mean further from the reference's than the hybrid's worst or 0.5%, no contrast ratio
// further from 1 than the hybrid's or kContrastTolerance); on a third the cheapest hybrid swept
// (any D, dicing rate and spp, the default included) whose every depth band is within
// kConsistentBandPct of the reference and whose contrast ratios are within kContrastTolerance of
// 1, against the default hybrid, or "none"; then the reference's verdict.
// Four lines starting "trade: ". Throws meso::Error without a default hybrid.
std::string tradeSummary(const std::vector<TradeResult>& results, const ReferenceStudy& study);

// A displacement-only configuration between two swept spp values: on one dicing rate and relief
// samples value, `fewer` (fewer spp) has an rmse above the target and `more` (the next swept spp)
// one at or below it. Its rmse falls as a power of spp between them (a line in log rmse against log
// spp: sampling noise with stratified samples, plus the geometry's fixed error) and its time grows
// linearly with spp (tessellation and BVH once, every sample alike): `spp` is where that line
// reaches the target and `seconds` the time there.
struct InterpolatedDisplacement {
  const TradeResult* fewer = nullptr;
  const TradeResult* more = nullptr;
  double spp = 0.0;
  double seconds = 0.0;
};

// The cheapest such interpolation over every displacement-only series of `results` that brackets
// `rmse`; nullopt when none does (every series is above it at its most spp, or below at its
// fewest). The grid alone can overstate what equal rmse costs displacement by up to the spp step
// (4x by default): this is the figure between the grid points.
std::optional<InterpolatedDisplacement> interpolatedAsAccurate(
    const std::vector<TradeResult>& results, double rmse);

// "meso: trade 3/12 NAME  seconds MiB mp rmse mae mean" for stderr.
std::string progressLine(const TradeResult& r, size_t index, size_t count);

}  // namespace meso::trade
