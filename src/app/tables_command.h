// `meso tables SCENE`: builds the appearance tables of the relief levels the scene uses, reports
// build time, size and cache hit or miss per level, and writes PNG plots of them.
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
  std::filesystem::path outDir =
      "out/tables";  // plots: <material>_level<i>_histogram.png, _brdf.png
  bool noPlots = false;
};

// The `tables` command, registered on `cli` with its options.
std::unique_ptr<Command> makeTablesCommand(CLI::App& cli);

}  // namespace meso::app
