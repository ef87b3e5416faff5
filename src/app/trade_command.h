// `meso trade`: the speed/accuracy trade of DESIGN.md section 7. Time, memory and error of the
// hybrid (algorithm auto over D x spp and dicing rate x spp) and of displacement alone (dicing rate
// x spp) against a full-displacement reference refined until it converges (or a warning says it did
// not); optionally the temporal stability of the hybrid near its thresholds.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace meso::app {

struct TradeCommandOptions {
  std::filesystem::path scene;
  std::filesystem::path outDir = "out/trade";  // trade.csv, trade.png, temporal.csv
  std::string frames;                          // "A:B" of the scene's [path]; empty: every frame
  // The reference starts at referenceDicingRate and referenceSpp; each refinement halves the one
  // and doubles the other, until the mean changes by less than referenceTolerance and the rmse
  // between successive levels is below referenceRmseTolerance (both in percent of the mean
  // intensity), or the budget is spent (then a warning says how far from converged the last step
  // was). The rmse includes both levels' sampling noise, hence its own, looser tolerance.
  int referenceSpp = 64;
  float referenceDicingRate = 0.5f;                   // pixels
  float referenceTolerance = 0.5f;                    // percent of the mean intensity
  float referenceRmseTolerance = 2.0f;                // percent of the mean intensity
  int referenceMaxRefinements = 3;                    // levels after the first
  long long referenceMaxMicropolygons = 100'000'000;  // no level is started that would exceed it
  std::filesystem::path referenceCache;               // empty: ReferenceCache::defaultFolder(scene)
  bool noReferenceCache = false;
  std::vector<float> dValues{0.5f, 1.0f, 2.0f, 4.0f};
  std::vector<int> sppValues{1, 4, 16};
  std::vector<float> dicingRates{4.0f, 2.0f, 1.0f, 0.5f};        // displacement alone
  std::vector<float> hybridDicingRates{4.0f, 2.0f, 1.0f, 0.5f};  // the hybrid, at the scene's D
  std::optional<int> width, height;
  std::optional<int> threads;
  bool temporal = false;      // also measure frame-to-frame change in the transition bands
  bool temporalOnly = false;  // only the reference and the default hybrid (implies temporal)
  float band = 0.1f;          // half width of the T bands around e1..e4
  bool quiet = false;
};

// Renders every configuration, writes DIR/trade.csv and DIR/trade.png (and DIR/temporal.csv),
// prints the summary on stdout and progress on stderr. Throws meso::Error on bad values.
void runTrade(const TradeCommandOptions& options);

}  // namespace meso::app
