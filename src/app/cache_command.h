// `meso cache list|clear|prune`: what the table cache folder holds, emptying it, and evicting the
// least recently used tables down to a size.
#pragma once

#include <filesystem>
#include <string>

namespace meso::app {

struct CacheCommandOptions {
  std::filesystem::path cacheDir;  // empty: TableCache::defaultFolder()
  std::string to;                  // prune: target size ("500M"); empty: TableCache::defaultLimit()
};

// One line per table, least recently used first (file name, size, last use), then a total line.
void runCacheList(const CacheCommandOptions& options);
// Removes every table and lock file no other process holds; says how many and how many bytes.
void runCacheClear(const CacheCommandOptions& options);
// Removes least recently used tables until the rest take at most options.to.
void runCachePrune(const CacheCommandOptions& options);

}  // namespace meso::app
