// The sweep of `meso trade` (see trade_study.h).
#include "meso/trade/trade_study.h"

#include "meso/core/error.h"
#include "meso/trade/image_errors.h"
#include "meso/trade/trade_report.h"

#include <cmath>
#include <cstdio>

namespace meso::trade {
namespace {

template <class T>
void checkValues(const std::vector<T>& values, const char* option, double lo, double hi) {
  if (values.empty()) throw Error(std::string(option) + ": needs at least one value");
  for (T v : values)
    if (!std::isfinite(static_cast<double>(v)) || v < lo || v > hi)
      throw Error(std::string(option) + ": " + formatNumber(static_cast<double>(v)) +
                  " is outside [" + formatNumber(lo) + ", " + formatNumber(hi) + "]");
}

template <class T>
void checkValue(T value, const char* option, double lo, double hi) {
  checkValues(std::vector<T>{value}, option, lo, hi);
}

// The reference levels as rows, each against the last level.
std::vector<TradeResult> referenceRows(const ReferenceStudy& study) {
  std::vector<TradeResult> rows;
  for (size_t k = 0; k < study.levels.size(); ++k) {
    const ReferenceLevel& l = study.levels[k];
    const bool last = k + 1 == study.levels.size();
    const Configuration c{.name = last ? "reference" : "reference_l" + std::to_string(k),
                          .kind = Kind::Reference,
                          .D = 0.0f,
                          .spp = l.spp,
                          .dicingRate = l.dicingRate,
                          .reliefSamples = l.reliefSamples};
    rows.push_back({.config = c,
                    .seconds = l.render.seconds,
                    .peakRssMib = l.render.peakRssMib,
                    .micropolygons = l.render.micropolygons,
                    .geometryMib = l.render.geometryMib,
                    .errors = compareRenders(l.render, study.reference()),
                    .addedMib = l.render.addedMib});
  }
  return rows;
}

}  // namespace

void validateTradeSettings(const TradeSettings& s) {
  const ReferenceBudget& r = s.reference;
  checkValue(r.spp, "--reference-spp", 1, 65536);
  checkValue(r.dicingRate, "--reference-dicing-rate", 0.01, 1000);
  checkValue(r.tolerance, "--reference-tolerance", 1e-6, 100);
  checkValue(r.rmseTolerance, "--reference-rmse-tolerance", 1e-6, 1000);
  checkValue(r.maxRefinements, "--reference-max-refinements", 0, 12);
  checkValue(static_cast<double>(r.maxMicropolygons), "--reference-max-micropolygons", 1000, 1e12);
  checkValues(s.grid.hybridDicingRates, "--hybrid-dicing-rates", 0.01, 1000);
  checkValues(s.grid.dValues, "--d-values", 0, 1e6);
  checkValues(s.grid.sppValues, "--spp-values", 1, 65536);
  checkValues(s.grid.dicingRates, "--dicing-rates", 0.01, 1000);
  checkValues(s.grid.reliefSamples, "--relief-samples-values", 0, 16);
}

TradeStudy runTradeStudy(const Scene& scene, const std::vector<CameraSettings>& cameras,
                         const TradeSettings& settings, const ReferenceCache& cache,
                         const std::atomic<bool>* cancel) {
  const std::vector<Configuration> configs = configurations(settings.grid, scene);
  for (const Configuration& c : configs)
    sceneFor(scene, c);  // checks every D before rendering anything
  bool warnedRss = false;
  MeasureOptions measure{.keepFilms = false,
                         .cancel = cancel,
                         .warnedRss = &warnedRss,
                         .progress = !settings.quiet,
                         .memoryLimitBytes = settings.memoryLimitBytes};
  TradeStudy study;
  study.reference =
      convergeReference(scene, settings.reference, cameras, cache, measure, settings.quiet);
  if (!study.reference.converged)
    std::fprintf(stderr, "meso: WARNING: %s\n", referenceVerdict(study.reference).c_str());
  study.results = referenceRows(study.reference);
  const MeasuredRender& reference = study.reference.reference();
  for (size_t i = 0; i < configs.size(); ++i) {
    const Configuration& c = configs[i];
    measure.keepFilms = settings.temporal && c.defaultHybrid;
    MeasuredRender r = renderMeasured(scene, c, cameras, measure);
    const TradeResult result{.config = c,
                             .seconds = r.seconds,
                             .peakRssMib = r.peakRssMib,
                             .micropolygons = r.micropolygons,
                             .geometryMib = r.geometryMib,
                             .errors = compareRenders(r, reference),
                             .addedMib = r.addedMib};
    study.results.push_back(result);
    if (!settings.quiet) std::fputs(progressLine(result, i, configs.size()).c_str(), stderr);
    if (c.defaultHybrid) study.defaultHybrid = std::move(r);
  }
  return study;
}

}  // namespace meso::trade
