// `meso render`: options as parsed by the CLI, and the command itself.
#pragma once

#include "interrupt.h"

#include "meso/scene/choices.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace meso::app {

struct RenderCommandOptions {
  std::filesystem::path scene;
  std::filesystem::path output;     // .exr; empty: out/<scene stem>.exr
  std::filesystem::path statsFile;  // empty: none
  std::optional<int> spp;
  std::optional<int> threads;
  std::optional<uint64_t> seed;
  std::optional<Algorithm> algorithm;
  std::optional<int> tessellationRate;
  std::optional<int> width, height;
  std::optional<float> dicingRate;
  std::optional<DicingMetric> dicingMetric;
  std::optional<float> reliefSamples;
  std::optional<int64_t> maxMicropolygons;
  std::optional<ShadingNormals> normals;
  std::optional<float> transitionD, transitionEps;
  std::vector<float> thresholds;  // e1,e2,e3,e4; empty: the scene's
  bool falseColour = false;
  bool noBumpFilter = false;
  bool noShadows = false;  // render.shadows = false     // --algorithm bump: point-sampled slopes
                           // instead of Schilling's pyramids
  bool quiet = false;
  std::string frames;           // "A:B" (inclusive) or "A"; empty: every frame of the path
  std::string shard;            // "i/n": render frames f with f % n == i
  bool overwrite = false;       // re-render frames already complete on disk
  std::filesystem::path video;  // assemble the frames' PNGs with ffmpeg
};

// Renders and writes the EXR, its PNG preview and (optionally) the stats JSON. Throws meso::Error.
void runRender(const RenderCommandOptions& options);

}  // namespace meso::app
