// `meso render`: options as parsed by the CLI, and the command itself.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace meso::app {

struct RenderCommandOptions {
  std::filesystem::path scene;
  std::filesystem::path output;      // .exr; empty: out/<scene stem>.exr
  std::filesystem::path statsFile;   // empty: none
  std::optional<int> spp;
  std::optional<int> threads;
  std::optional<uint64_t> seed;
  std::optional<std::string> algorithm;
  std::optional<int> tessellationRate;
  std::optional<int> width, height;
  bool falseColour = false;
  bool quiet = false;
};

// Renders and writes the EXR, its PNG preview and (optionally) the stats JSON. Throws meso::Error.
void runRender(const RenderCommandOptions& options);

}  // namespace meso::app
