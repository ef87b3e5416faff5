// trade.csv and the summary of `meso trade` (see trade_report.h).
#include "meso/trade/trade_report.h"

#include "meso/core/error.h"
#include "meso/render/local_contrast.h"
#include "meso/trade/pareto_front.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
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
  return fmt::format(
      "# reference level {}: dicing_rate {:g}, relief_samples {:g}, spp {}, micropolygons {}, "
      "seconds {:.6g}{}, mean_change_pct {}, rmse_change_pct {}, band_change_pct {}\n",
      k, l.dicingRate, l.reliefSamples, l.spp, l.render.micropolygons, l.render.seconds,
      l.fromCache ? " (cached)" : "", k ? formatNumber(l.meanChangePct) : "",
      k ? formatNumber(l.rmseChangePct) : "", bandList(l.bandChangePct));
}

// The worst contrast ratio, "" when no depth band shows relief.
std::string contrastCell(double ratio) {
  if (std::isnan(ratio)) return "";
  return fmt::format("{:.4g}", ratio);
}

// ", worst contrast ratio 0.93", or nothing when no depth band shows relief.
std::string contrastText(double ratio) {
  return std::isnan(ratio) ? "" : ", worst contrast ratio " + contrastCell(ratio);
}

std::string row(const TradeResult& r) {
  const Configuration& c = r.config;
  // D is left empty where the algorithm does not use it (displacement alone).
  const std::string D = c.kind == Kind::Hybrid ? formatNumber(c.D) : "";
  // relief_samples is left empty for the hybrid, which dices by pixels where it displaces.
  const std::string samples = c.kind == Kind::Hybrid ? "" : formatNumber(c.reliefSamples);
  return fmt::format(
      "{},{},{},{},{:g},{},{:.6g},{:.1f},{},{:.6g},{:.6g},{:.6g},{:.1f},{:.1f},{:.4g},{}\n", c.name,
      algorithmName(c.kind), D, c.spp, c.dicingRate, samples, r.seconds, r.peakRssMib,
      r.micropolygons, r.errors.meanAbsError, r.errors.rmse, r.errors.intensityErrorPct,
      r.geometryMib, r.addedMib, r.errors.worstBandPct, contrastCell(r.errors.worstContrastRatio));
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
// 0, no depth band's mean further from the reference's than bandPct percent and no contrast ratio
// further from 1 than contrastTolerance where the reference shows relief.
const TradeResult* cheapestAsAccurate(const std::vector<TradeResult>& results, double rmse,
                                      double bandPct, double contrastTolerance = 0.0) {
  const TradeResult* cheapest = nullptr;
  for (const TradeResult& r : results) {
    const double ratio = r.errors.worstContrastRatio;
    if (r.config.kind == Kind::Displacement && r.errors.rmse <= rmse &&
        (bandPct < 0.0 || (std::abs(r.errors.worstBandPct) <= bandPct &&
                           (std::isnan(ratio) || std::abs(ratio - 1.0) <= contrastTolerance))) &&
        (!cheapest || r.seconds < cheapest->seconds))
      cheapest = &r;
  }
  return cheapest;
}

// The fastest hybrid configuration (the default included) whose every depth band's mean is within
// kConsistentBandPct of the reference's and whose worst contrast ratio is within kContrastTolerance
// of 1 (or no band shows relief): the strict criterion, whatever the default hybrid's own figures.
const TradeResult* cheapestConsistentHybrid(const std::vector<TradeResult>& results) {
  const TradeResult* cheapest = nullptr;
  for (const TradeResult& r : results) {
    const double ratio = r.errors.worstContrastRatio;
    if (r.config.kind == Kind::Hybrid && std::abs(r.errors.worstBandPct) <= kConsistentBandPct &&
        (std::isnan(ratio) || std::abs(ratio - 1.0) <= kContrastTolerance) &&
        (!cheapest || r.seconds < cheapest->seconds))
      cheapest = &r;
  }
  return cheapest;
}

// "trade: cheapest hybrid swept within 0.5% ... and 10% ...: D 8, 1 px, 4 spp: ...": which D,
// dicing rate and spp buy the criterion for least time, against the default hybrid.
std::string hybridLine(const std::vector<TradeResult>& results, const TradeResult& h) {
  const std::string head = fmt::format(
      "trade: cheapest hybrid swept within {:g}% of the reference in every depth band and {:g}% in "
      "local contrast: ",
      kConsistentBandPct, 100.0 * kContrastTolerance);
  const TradeResult* best = cheapestConsistentHybrid(results);
  if (!best) return head + "none";
  if (best == &h) return head + "the default hybrid";
  return head +
         fmt::format(
             "D {:g}, {:g} px, {} spp: {:.3g} s ({:.3g}x the default hybrid's time), {} "
             "micropolygons ({:.3g}x), peak {:.1f} MiB, worst band {:+.3g}%{}",
             best->config.D, best->config.dicingRate, best->config.spp, best->seconds,
             ratio(best->seconds, h.seconds), best->micropolygons,
             ratio(static_cast<double>(best->micropolygons), static_cast<double>(h.micropolygons)),
             best->peakRssMib, best->errors.worstBandPct,
             contrastText(best->errors.worstContrastRatio));
}

// Ahead of `text`: "speedup <d / h>x", and " (the hybrid is slower)" when it is.
std::string speedupText(double hybridSeconds, double displacementSeconds) {
  return fmt::format("speedup {:.2f}x{}", ratio(displacementSeconds, hybridSeconds),
                     displacementSeconds < hybridSeconds ? " (the hybrid is slower)" : "");
}

// "; interpolated over spp: ..." when the interpolation is cheaper than the swept `cheapest`.
std::string interpolatedText(const TradeResult& h, const std::vector<TradeResult>& results,
                             const TradeResult* cheapest) {
  const std::optional<InterpolatedDisplacement> i = interpolatedAsAccurate(results, h.errors.rmse);
  if (!i || (cheapest && cheapest->seconds <= i->seconds)) return "";
  return fmt::format(
      "; interpolated between the swept spp: displacement-only (dicing {:g} px, relief samples "
      "{:g}) reaches that rmse at about {:.3g} spp ({} spp: {:.4g}, {} spp: {:.4g}) in about "
      "{:.3g} s: {}",
      i->fewer->config.dicingRate, i->fewer->config.reliefSamples, i->spp, i->fewer->config.spp,
      i->fewer->errors.rmse, i->more->config.spp, i->more->errors.rmse, i->seconds,
      speedupText(h.seconds, i->seconds));
}

// "<ratio>x", or "n/a" when the displacement configuration's figure is 0 (a peak that did not rise
// above the process's baseline: a ratio to it says nothing).
std::string ratioText(double hybrid, double displacement) {
  if (!(displacement > 0.0)) return "n/a";
  return fmt::format("{:.3g}x", ratio(hybrid, displacement));
}

std::string comparison(const TradeResult& h, const TradeResult& d, const char* as, const char* at) {
  return fmt::format(
      "cheapest displacement-only {} (dicing {:g} px, relief samples {:g}, {} spp) {:.3g} s, rmse "
      "{:.4g}, worst band {:+.3g}%{}: {}; hybrid / displacement at {}: time {:.3g}x, peak memory "
      "{:.3g}x ({} of what each added above the process's baseline), geometry memory {:.3g}x, "
      "micropolygons {:.3g}x, spp {:.3g}x",
      as, d.config.dicingRate, d.config.reliefSamples, d.config.spp, d.seconds, d.errors.rmse,
      d.errors.worstBandPct, contrastText(d.errors.worstContrastRatio),
      speedupText(h.seconds, d.seconds), at, ratio(h.seconds, d.seconds),
      ratio(h.peakRssMib, d.peakRssMib), ratioText(h.addedMib, d.addedMib),
      ratio(h.geometryMib, d.geometryMib),
      ratio(static_cast<double>(h.micropolygons), static_cast<double>(d.micropolygons)),
      ratio(h.config.spp, d.config.spp));
}

}  // namespace

std::optional<InterpolatedDisplacement> interpolatedAsAccurate(
    const std::vector<TradeResult>& results, double rmse) {
  std::optional<InterpolatedDisplacement> best;
  if (!(rmse > 0.0) || !std::isfinite(rmse)) return best;
  const auto sameSeries = [](const Configuration& a, const Configuration& b) {
    return a.kind == Kind::Displacement && b.kind == Kind::Displacement &&
           a.dicingRate == b.dicingRate && a.reliefSamples == b.reliefSamples;
  };
  for (const TradeResult& a : results) {
    if (a.config.kind != Kind::Displacement || !(a.errors.rmse > rmse)) continue;
    // The same series' next swept spp above a's.
    const TradeResult* b = nullptr;
    for (const TradeResult& r : results)
      if (sameSeries(a.config, r.config) && r.config.spp > a.config.spp &&
          (!b || r.config.spp < b->config.spp))
        b = &r;
    if (!b || !(b->errors.rmse <= rmse) || !(b->errors.rmse > 0.0)) continue;
    const double x0 = std::log(a.config.spp), x1 = std::log(b->config.spp);
    const double t = std::log(rmse / a.errors.rmse) / std::log(b->errors.rmse / a.errors.rmse);
    const double spp = std::exp(x0 + std::clamp(t, 0.0, 1.0) * (x1 - x0));
    const double seconds = a.seconds + (b->seconds - a.seconds) * (spp - a.config.spp) /
                                           (b->config.spp - a.config.spp);
    if (!std::isfinite(seconds)) continue;
    if (!best || seconds < best->seconds)
      best = InterpolatedDisplacement{.fewer = &a, .more = b, .spp = spp, .seconds = seconds};
  }
  return best;
}

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
       "mean_intensity_error_pct,geometry_mib,peak_added_mib,worst_band_error_pct,worst_contrast_"
       "ratio\n";
  for (const TradeResult& r : results) s += row(r);
  return s;
}

std::string tradeSummary(const std::vector<TradeResult>& results, const ReferenceStudy& study) {
  const TradeResult& h = defaultHybrid(results);
  const double hRatio = h.errors.worstContrastRatio;
  const std::string head = fmt::format(
      "trade: default hybrid (D {:g}, {:g} px, {} spp) {:.3g} s, rmse {:.4g}, mean error {:.3g}%, "
      "worst band {:+.3g}%{}{}",
      h.config.D, h.config.dicingRate, h.config.spp, h.seconds, h.errors.rmse,
      h.errors.intensityErrorPct, h.errors.worstBandPct, contrastText(hRatio),
      asDetailed(hRatio) ? "" : " (NOT as detailed as the reference)");
  const TradeResult* cheapest = cheapestAsAccurate(results, h.errors.rmse, -1.0);
  // Intensity consistency and detail too: no depth band further from the reference than the
  // hybrid's worst (at least 0.5%, the reference's own tolerance), no contrast ratio further from 1
  // than the hybrid's (at least kContrastTolerance).
  const double band = std::max(std::abs(h.errors.worstBandPct), kConsistentBandPct);
  const double detail = std::isnan(hRatio) ? kContrastTolerance
                                           : std::max(std::abs(hRatio - 1.0), kContrastTolerance);
  const TradeResult* consistent = cheapestAsAccurate(results, h.errors.rmse, band, detail);
  const std::string bandLine = fmt::format(
      "trade: as consistent and as detailed too (every depth band's mean within {:.3g}% of the "
      "reference's, its local contrast within {:.3g}% where the reference shows relief): ",
      band, 100.0 * detail);
  return head +
         (cheapest ? "; " + comparison(h, *cheapest, "as accurate", "equal rmse")
                   : "; no displacement-only configuration swept is as accurate") +
         interpolatedText(h, results, cheapest) + "\n" + bandLine +
         (consistent
              ? comparison(h, *consistent, "as accurate", "equal rmse, band error and contrast")
              : "no displacement-only configuration swept is as accurate, consistent and "
                "detailed") +
         "\n" + hybridLine(results, h) + "\n" + (study.converged ? "trade: " : "trade: WARNING: ") +
         referenceVerdict(study);
}

std::string progressLine(const TradeResult& r, size_t index, size_t count) {
  return fmt::format(
      "meso: trade {}/{} {:<28} {:>8.3f} s {:>8.1f} MiB {:>10} mp  rmse {:.5g}  mae {:.5g}  mean "
      "error {:.3g}%  worst band {:+.3g}%  contrast ratio {}\n",
      index + 1, count, r.config.name, r.seconds, r.peakRssMib, r.micropolygons, r.errors.rmse,
      r.errors.meanAbsError, r.errors.intensityErrorPct, r.errors.worstBandPct,
      std::isnan(r.errors.worstContrastRatio) ? "-" : contrastCell(r.errors.worstContrastRatio));
}

}  // namespace meso::trade
