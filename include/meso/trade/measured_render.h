// One configuration of `meso trade` rendered over the frames, with what it cost: wall time of
// prepareFrame plus renderFrame (prepareRenderContext excluded: its meshes, limit surfaces and
// tables are shared by every configuration and cached on disk), peak RSS, displaced micropolygons
// and the memory of the displaced meshes with their Embree scene.
#pragma once

#include "meso/core/image.h"
#include "meso/core/memory_budget.h"
#include "meso/scene/scene.h"
#include "meso/trade/configuration.h"

#include <atomic>
#include <cstddef>
#include <string>
#include <vector>

namespace meso::trade {

// Beauty R, G, B, row-major and interleaved.
struct RgbImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
  const float* at(int x, int y) const {
    return &rgb[(static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * 3];
  }
};

// The beauty channels of a film of renderFrame's (FilmLayout).
RgbImage beautyOf(const Image& film);

struct MeasuredRender {
  double seconds = 0.0;
  double peakRssMib = 0.0;
  // The peak above the resident memory when the configuration started: what it needed itself,
  // without the process's libraries, the reference images and the other state trade holds.
  double addedMib = 0.0;
  size_t micropolygons = 0;  // the most of any frame
  double geometryMib = 0.0;  // the most of any frame
  float coarsening = 1.0f;   // > 1: the micropolygon cap coarsened some frame's dicing
  std::vector<RgbImage> beauty;
  std::vector<std::vector<float>> depth;  // reference only: depth.Z per frame (0: no hit)
  // The same frames rendered again with render/local_contrast.h's secondSeed on the same geometry,
  // neither timed nor counted in the peaks: the sampling noise of beauty, for the local contrast.
  std::vector<RgbImage> secondBeauty;
  std::vector<std::vector<float>> secondDepth;  // reference only
  std::vector<Image> films;                     // whole films, only when asked for
};

struct MeasureOptions {
  bool keepFilms = false;
  // Polled before each frame and by the renderer; set: throws meso::Interrupted.
  const std::atomic<bool>* cancel = nullptr;
  // Set once the peak RSS could not be reset (a warning was printed then, only once).
  bool* warnedRss = nullptr;
  bool progress = true;  // the tables' progress bar (drawn only when stderr is a terminal)
  uint64_t memoryLimitBytes = defaultMemoryLimitBytes();  // PrepareOptions::memoryLimitBytes
};

// Renders `c` of `base` through `cameras`, each frame with the scene's seed and then with the
// second seed; ctx warnings go to stderr, named by the configuration.
MeasuredRender renderMeasured(const Scene& base, const Configuration& c,
                              const std::vector<CameraSettings>& cameras,
                              const MeasureOptions& options);

}  // namespace meso::trade
