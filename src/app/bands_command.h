// `meso bands`: splits one height map into band-limited relief levels (Becker & Max 1993, 4.3).
// It writes OUT/<stem>_band<k>.exr (k = 1 is the lowest band; one float channel Y each), prints one
// CSV row per band (file, freq, crossovers, range) and the reconstruction error of their sum, and a
// [[materials.relief]] snippet for a scene.
#pragma once

#include "command.h"

#include <filesystem>
#include <memory>

namespace meso::app {

struct BandsCommandOptions {
  std::filesystem::path height;  // any image OpenImageIO reads
  int levels = 3;
  std::filesystem::path outDir = "out/bands";
  bool clamp = false;  // the map does not tile: mirror it before filtering
};

// The `bands` command, registered on `cli` with its options.
std::unique_ptr<Command> makeBandsCommand(CLI::App& cli);

}  // namespace meso::app
