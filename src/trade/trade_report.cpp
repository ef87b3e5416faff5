// trade.csv and the summary of `meso trade` (see trade_report.h).
#include "meso/trade/trade_report.h"

#include "meso/core/error.h"
#include "meso/trade/pareto_front.h"

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
  std::snprintf(line, sizeof line, "%s,%s,%s,%d,%g,%s,%.6g,%.1f,%zu,%.6g,%.6g,%.6g,%.1f,%.1f\n",
                c.name.c_str(), algorithmName(c.kind), D.c_str(), c.spp, c.dicingRate,
                samples.c_str(), r.seconds, r.peakRssMib, r.micropolygons, r.errors.meanAbsError,
                r.errors.rmse, r.errors.intensityErrorPct, r.geometryMib, r.addedMib);
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

const TradeResult* cheapestAsAccurate(const std::vector<TradeResult>& results, double rmse) {
  const TradeResult* cheapest = nullptr;
  for (const TradeResult& r : results)
    if (r.config.kind == Kind::Displacement && r.errors.rmse <= rmse &&
        (!cheapest || r.seconds < cheapest->seconds))
      cheapest = &r;
  return cheapest;
}

std::string comparison(const TradeResult& h, const TradeResult& d) {
  char buf[768];
  std::snprintf(
      buf, sizeof buf,
      "; cheapest displacement-only as accurate (dicing %g px, %d spp) %.3g s, rmse %.4g: "
      "speedup %.2fx%s; hybrid / displacement at equal rmse: time %.3gx, peak memory %.3gx "
      "(%.3gx of what each added above the process's baseline), geometry memory %.3gx, "
      "micropolygons %.3gx, spp %.3gx",
      d.config.dicingRate, d.config.spp, d.seconds, d.errors.rmse, ratio(d.seconds, h.seconds),
      d.seconds < h.seconds ? " (the hybrid is slower)" : "", ratio(h.seconds, d.seconds),
      ratio(h.peakRssMib, d.peakRssMib), ratio(h.addedMib, d.addedMib),
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
       "mean_intensity_error_pct,geometry_mib,peak_added_mib\n";
  for (const TradeResult& r : results) s += row(r);
  return s;
}

std::string tradeSummary(const std::vector<TradeResult>& results, const ReferenceStudy& study) {
  const TradeResult& h = defaultHybrid(results);
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "trade: default hybrid (D %g, %g px, %d spp) %.3g s, rmse %.4g, mean %+.3g%%",
                h.config.D, h.config.dicingRate, h.config.spp, h.seconds, h.errors.rmse,
                h.errors.intensityErrorPct);
  const TradeResult* cheapest = cheapestAsAccurate(results, h.errors.rmse);
  return std::string(buf) +
         (cheapest ? comparison(h, *cheapest)
                   : "; no displacement-only configuration swept is as accurate") +
         "\n" + (study.converged ? "trade: " : "trade: WARNING: ") + referenceVerdict(study);
}

std::string progressLine(const TradeResult& r, size_t index, size_t count) {
  char line[320];
  std::snprintf(
      line, sizeof line,
      "meso: trade %zu/%zu %-28s %8.3f s %8.1f MiB %10zu mp  rmse %.5g  mae %.5g  mean %+.3g%%\n",
      index + 1, count, r.config.name.c_str(), r.seconds, r.peakRssMib, r.micropolygons,
      r.errors.rmse, r.errors.meanAbsError, r.errors.intensityErrorPct);
  return line;
}

}  // namespace meso::trade
