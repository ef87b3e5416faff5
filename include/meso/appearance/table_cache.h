// The on-disk cache of appearance tables (DESIGN.md section 4): one file per key, verified on load;
// a stale, truncated or corrupt file is rebuilt, never trusted.
#pragma once

#include "meso/core/hash.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace meso {

// Bump this whenever the layout or meaning of any cached table changes: old files become misses.
inline constexpr uint32_t kTableFormatVersion =
    5;  // 4: masses only, view-azimuth slices, word checksum; 5: BRDF theta_L to pi

class TableCache {
 public:
  // An empty folder disables the cache (every load misses, store does nothing).
  explicit TableCache(std::filesystem::path folder);
  // $MESO_CACHE_DIR, else $XDG_CACHE_HOME/meso, else $HOME/.cache/meso, else none.
  static std::filesystem::path defaultFolder();

  const std::filesystem::path& folder() const { return folder_; }
  std::filesystem::path fileFor(uint64_t key) const;
  // The cached floats, or nullopt on a miss. A file that exists but fails a check (magic, version,
  // key, size, checksum) is deleted and *warning says why, so the caller rebuilds it.
  std::optional<std::vector<float>> load(uint64_t key, std::string* warning) const;
  // Writes atomically (temporary file, then rename). Failure to write is only a warning.
  void store(uint64_t key, std::span<const float> data, std::string* warning) const;

 private:
  std::filesystem::path folder_;
};

}  // namespace meso
