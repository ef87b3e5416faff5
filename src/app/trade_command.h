// `meso trade`: the speed/accuracy trade of DESIGN.md section 7. Time, memory and error of the hybrid
// (algorithm auto over D x spp) and of displacement alone (dicing rate x spp) against a converged
// full-displacement reference; optionally the temporal stability of the hybrid near its thresholds.
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
  int referenceSpp = 64;
  float referenceDicingRate = 0.5f;            // pixels
  std::vector<float> dValues{0.5f, 1.0f, 2.0f, 4.0f};
  std::vector<int> sppValues{1, 4, 16};
  std::vector<float> dicingRates{4.0f, 2.0f, 1.0f, 0.5f};
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
