// `meso trade`: the speed/accuracy trade of DESIGN.md section 7 (the study itself is the library
// in include/meso/trade/). Time, memory and error of the hybrid (algorithm auto over D x spp and
// dicing rate x spp) and of displacement alone (dicing rate x spp) against a full-displacement
// reference refined until it converges (or a warning says it did not); optionally the temporal
// stability of the hybrid near its thresholds. It writes DIR/trade.csv, DIR/trade.png (plotted by
// tools/plot_trade.py from the CSV, when python3 with matplotlib is there) and DIR/temporal.csv,
// and prints the summary on stdout and progress on stderr.
#pragma once

#include "command.h"

#include "meso/trade/trade_study.h"

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace meso::app {

struct TradeCommandOptions {
  std::filesystem::path scene;
  std::vector<std::string> set;                // --set KEY=VALUE, in order
  std::filesystem::path outDir = "out/trade";  // trade.csv, trade.png, temporal.csv
  std::string frames;                          // "A:B" of the scene's [path]; empty: every frame
  trade::TradeSettings settings;               // the reference's budget and the swept values
  std::filesystem::path referenceCache;        // empty: ReferenceCache::defaultFolder(scene)
  bool noReferenceCache = false;
  std::optional<int> width, height;
  std::optional<int> threads;
  bool temporalOnly = false;  // only the reference and the default hybrid (implies --temporal)
  float band = 0.1f;          // half width of the T bands around e1..e4
};

// The `trade` command, registered on `cli` with its options.
std::unique_ptr<Command> makeTradeCommand(CLI::App& cli);

}  // namespace meso::app
