// `meso cache list|clear|prune`: what the table cache folder holds, emptying it, and evicting the
// least recently used tables down to a size.
#pragma once

#include "command.h"

#include <filesystem>
#include <memory>
#include <string>

namespace meso::app {

struct CacheCommandOptions {
  std::filesystem::path cacheDir;  // empty: TableCache::defaultFolder()
  std::string to;                  // prune: target size ("500M"); empty: TableCache::defaultLimit()
};

// The `cache` command (list: one line per table, least recently used first, then a total; clear:
// removes every table and lock file no other process holds; prune: removes least recently used
// tables until the rest take at most --to), registered on `cli` with its options.
std::unique_ptr<Command> makeCacheCommand(CLI::App& cli);

}  // namespace meso::app
