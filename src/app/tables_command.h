// `meso tables SCENE`: builds the appearance tables of the relief levels the scene uses, reports
// build time, size and cache hit or miss per level, and writes their data as CSV and plots of them
// (tools/plot_tables.py, when python3 with matplotlib is there).
#pragma once

#include "command.h"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace meso::app {

struct TablesCommandOptions {
  std::filesystem::path scene;
  std::vector<std::string> set;  // --set KEY=VALUE, in order
  // <material>_level<i>_histogram.csv and .png, _brdf.csv and .png
  std::filesystem::path outDir = "out/tables";
  bool noPlots = false;
};

// The `tables` command, registered on `cli` with its options.
std::unique_ptr<Command> makeTablesCommand(CLI::App& cli);

}  // namespace meso::app
