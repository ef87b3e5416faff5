// trade.csv and the summary of `meso trade` (see trade_report.h).
#include "meso/trade/trade_report.h"

#include "meso/core/error.h"
#include "meso/trade/pareto_front.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace meso::trade {
namespace {

// "a;b;c".
std::string joined(const std::vector<std::string>& items) {
  std::string text;
  for (size_t i = 0; i < items.size(); ++i) text += (i > 0 ? ";" : "") + items[i];
  return text;
}

std::string bandList(const std::vector<double>& bands) {
  std::vector<std::string> items;
  for (double b : bands) items.push_back(formatNumber(b));
  return joined(items);
}

std::string levelComment(const ReferenceLevel& l, size_t k) {
  char line[640];
  std::snprintf(line, sizeof line,
                "# reference level %zu: dicing_rate %g, relief_samples %g, spp %d, micropolygons "
                "%zu, seconds %.6g%s, mean_change_pct %s, rmse_change_pct %s, band_change_pct %s\n",
                k, l.dicingRate, l.reliefSamples, l.spp, l.render.micropolygons, l.render.seconds,
                l.fromCache ? " (cached)" : "", k ? formatNumber(l.meanChangePct).c_str() : "",
                k ? formatNumber(l.rmseChangePct).c_str() : "", bandList(l.bandChangePct).c_str());
  return line;
}

std::string row(const TradeResult& r) {
  const Configuration& c = r.config;
  // D is left empty where the algorithm does not use it (displacement alone).
  const std::string D = c.kind == Kind::Hybrid ? formatNumber(c.D) : "";
  char line[640];
  // relief_samples is left empty for the hybrid, which dices by pixels where it displaces.
  const std::string samples = c.kind == Kind::Hybrid ? "" : formatNumber(c.reliefSamples);
  std::snprintf(line, sizeof line,
                "%s,%s,%s,%d,%g,%s,%.6g,%.1f,%zu,%.6g,%.6g,%.6g,%.1f,%.1f,%.4g\n", c.name.c_str(),
                algorithmName(c.kind), D.c_str(), c.spp, c.dicingRate, samples.c_str(), r.seconds,
                r.peakRssMib, r.micropolygons, r.errors.meanAbsError, r.errors.rmse,
                r.errors.intensityErrorPct, r.geometryMib, r.addedMib, r.errors.worstBandPct);
  return line;
}

const TradeResult& defaultHybrid(const std::vector<TradeResult>& results) {
  for (const TradeResult& r : results)
    if (r.config.defaultHybrid) return r;
  throw Error("trade: internal: no default hybrid configuration");
}

double ratio(double a, double b) {
  return b > 0.0 ? a / b : (a > 0.0 ? std::numeric_limits<double>::infinity() : 1.0);
}

// The fastest displacement-only configuration with an rmse of at most `rmse` and, when bandPct >=
// 0, no depth band's mean further from the reference's than bandPct percent.
const TradeResult* cheapestAsAccurate(const std::vector<TradeResult>& results, double rmse,
                                      double bandPct) {
  const TradeResult* cheapest = nullptr;
  for (const TradeResult& r : results)
    if (r.config.kind == Kind::Displacement && r.errors.rmse <= rmse &&
        (bandPct < 0.0 || std::abs(r.errors.worstBandPct) <= bandPct) &&
        (!cheapest || r.seconds < cheapest->seconds))
      cheapest = &r;
  return cheapest;
}

// "<ratio>x", or "n/a" when the displacement configuration's figure is 0 (a peak that did not rise
// above the process's baseline: a ratio to it says nothing).
std::string ratioText(double hybrid, double displacement) {
  if (!(displacement > 0.0)) return "n/a";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3gx", ratio(hybrid, displacement));
  return buf;
}

std::string comparison(const TradeResult& h, const TradeResult& d, const char* as, const char* at) {
  char buf[900];
  std::snprintf(
      buf, sizeof buf,
      "cheapest displacement-only %s (dicing %g px, relief samples %g, %d spp) %.3g s, rmse "
      "%.4g, worst band %+.3g%%: speedup %.2fx%s; hybrid / displacement at %s: time %.3gx, peak "
      "memory %.3gx (%s of what each added above the process's baseline), geometry memory "
      "%.3gx, micropolygons %.3gx, spp %.3gx",
      as, d.config.dicingRate, d.config.reliefSamples, d.config.spp, d.seconds, d.errors.rmse,
      d.errors.worstBandPct, ratio(d.seconds, h.seconds),
      d.seconds < h.seconds ? " (the hybrid is slower)" : "", at, ratio(h.seconds, d.seconds),
      ratio(h.peakRssMib, d.peakRssMib), ratioText(h.addedMib, d.addedMib).c_str(),
      ratio(h.geometryMib, d.geometryMib),
      ratio(static_cast<double>(h.micropolygons), static_cast<double>(d.micropolygons)),
      ratio(h.config.spp, d.config.spp));
  return buf;
}

}  // namespace

std::string tradeCsv(const std::vector<TradeResult>& results, const ReferenceStudy& study) {
  std::string s = "# " + referenceVerdict(study) + "\n";
  for (size_t k = 0; k < study.levels.size(); ++k) s += levelComment(study.levels[k], k);
  std::vector<std::string> front;
  for (size_t i : paretoFront(results)) front.push_back(results[i].config.name);
  s += "# pareto_front: " + joined(front) + "\n";
  for (const TradeResult& r : results)
    if (r.config.defaultHybrid) s += "# default_hybrid: " + r.config.name + "\n";
  s += "name,algorithm,D,spp,dicing_rate,relief_samples,seconds,peak_rss_mib,micropolygons,mean_"
       "abs_error,rmse,"
       "mean_intensity_error_pct,geometry_mib,peak_added_mib,worst_band_error_pct\n";
  for (const TradeResult& r : results) s += row(r);
  return s;
}

std::string tradeSummary(const std::vector<TradeResult>& results, const ReferenceStudy& study) {
  const TradeResult& h = defaultHybrid(results);
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "trade: default hybrid (D %g, %g px, %d spp) %.3g s, rmse %.4g, mean error %.3g%%, "
                "worst band %+.3g%%",
                h.config.D, h.config.dicingRate, h.config.spp, h.seconds, h.errors.rmse,
                h.errors.intensityErrorPct, h.errors.worstBandPct);
  const TradeResult* cheapest = cheapestAsAccurate(results, h.errors.rmse, -1.0);
  // Intensity consistency too: no depth band further from the reference than the hybrid's worst
  // (at least 0.5%, the reference's own tolerance).
  const double band = std::max(std::abs(h.errors.worstBandPct), 0.5);
  const TradeResult* consistent = cheapestAsAccurate(results, h.errors.rmse, band);
  char bandLine[200];
  std::snprintf(bandLine, sizeof bandLine,
                "trade: as consistent too (every depth band's mean within %.3g%% of the "
                "reference's): ",
                band);
  return std::string(buf) +
         (cheapest ? "; " + comparison(h, *cheapest, "as accurate", "equal rmse")
                   : "; no displacement-only configuration swept is as accurate") +
         "\n" + bandLine +
         (consistent ? comparison(h, *consistent, "as accurate", "equal rmse and band error")
                     : "no displacement-only configuration swept is as accurate and consistent") +
         "\n" + (study.converged ? "trade: " : "trade: WARNING: ") + referenceVerdict(study);
}

std::string progressLine(const TradeResult& r, size_t index, size_t count) {
  char line[320];
  std::snprintf(line, sizeof line,
                "meso: trade %zu/%zu %-28s %8.3f s %8.1f MiB %10zu mp  rmse %.5g  mae %.5g  mean "
                "error %.3g%%  "
                "worst band %+.3g%%\n",
                index + 1, count, r.config.name.c_str(), r.seconds, r.peakRssMib, r.micropolygons,
                r.errors.rmse, r.errors.meanAbsError, r.errors.intensityErrorPct,
                r.errors.worstBandPct);
  return line;
}

}  // namespace meso::trade
