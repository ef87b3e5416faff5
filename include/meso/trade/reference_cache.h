// `meso trade`'s reference renders on disk: a full-displacement render at a fine dicing rate costs
// minutes, and repeated sweeps of the same scene need the same one. Keyed by a hash of the scene
// file, every file it reads and every setting that shapes the image; written atomically; a file
// that does not check out (size, magic, key or checksum) is removed and re-rendered, never trusted.
#pragma once

#include "meso/scene/scene.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace meso::trade {

// One reference level as rendered: beauty R, G, B and depth Z (row-major, interleaved, 4 floats a
// pixel) per frame, and what rendering it cost.
struct ReferenceRender {
  int width = 0, height = 0;
  std::vector<std::vector<float>> frames;  // RGBZ
  double seconds = 0.0;
  double peakRssMib = 0.0;
  double geometryMib = 0.0;
  double addedMib = 0.0;
  size_t micropolygons = 0;
};

// The key of a full-displacement render of `scene` (its render and camera settings as overridden
// on the command line) through `cameras` at `dicingRate` pixels and `spp` samples: the bytes of the
// scene file, its meshes and images, and the settings. Throws meso::Error if a file is unreadable.
uint64_t referenceKey(const Scene& scene, const std::vector<CameraSettings>& cameras,
                      float dicingRate, int spp);

class ReferenceCache {
 public:
  // An empty folder disables the cache.
  explicit ReferenceCache(std::filesystem::path folder) : folder_(std::move(folder)) {}
  // "references" in the scene's render.cache_dir, else in the table cache's default folder.
  static std::filesystem::path defaultFolder(const Scene& scene);

  const std::filesystem::path& folder() const { return folder_; }
  std::filesystem::path fileFor(uint64_t key) const;
  // The render stored under `key`, or nothing (no file, or a bad one: then *warning says why and
  // the file is removed).
  std::optional<ReferenceRender> load(uint64_t key, std::string* warning) const;
  // Stores atomically (temporary name, then rename); throws meso::Error if it cannot.
  void store(uint64_t key, const ReferenceRender& render) const;

 private:
  std::filesystem::path folder_;
};

}  // namespace meso::trade
