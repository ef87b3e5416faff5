// The JSON of `meso render --stats`: timings, memory, counters, per-frame figures and the
// settings the render used.
#pragma once

#include "meso/render/integrator.h"
#include "meso/render/render_context.h"
#include "meso/scene/scene.h"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace meso::app {

// What a run of frames measured, summed or maximised over its frames.
struct RenderRunStats {
  double parseSeconds = 0.0, renderSeconds = 0.0, writeSeconds = 0.0, totalSeconds = 0.0;
  size_t maxMicropolygons = 0, maxTriangles = 0;
  double geometryMibPerMillion = 0.0;  // of the frame with the most micropolygons
  double meshMibPerMillion = 0.0;      // meso's own part of it (the meshes, not Embree's)
  int rendered = 0, skipped = 0;
  int threads = 0;
  nlohmann::json perFrame = nlohmann::json::array();
};

// The settings the render used (after command-line overrides), for the stats file.
nlohmann::json settingsJson(const Scene& scene, const std::filesystem::path& output);

// One frame's entry of "frames".
nlohmann::json frameJson(int frame, const std::filesystem::path& exr, int64_t rays,
                         size_t triangles, const FrameGeometryStats& geometry, double renderSeconds,
                         double writeSeconds);

// The whole stats file.
nlohmann::json statsJson(const Scene& scene, const std::filesystem::path& output,
                         const RenderRunStats& run, const PrepareTimes& prep,
                         const RenderCounters& counters, const std::vector<std::string>& warnings);

}  // namespace meso::app
