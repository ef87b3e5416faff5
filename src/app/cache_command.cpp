#include "cache_command.h"

#include "meso/appearance/table_cache.h"
#include "meso/core/error.h"

#include <chrono>
#include <cstdio>
#include <ctime>

namespace meso::app {
namespace {

std::filesystem::path folderOf(const CacheCommandOptions& o) {
  const std::filesystem::path folder =
      o.cacheDir.empty() ? TableCache::defaultFolder() : o.cacheDir;
  if (folder.empty())
    throw Error(
        "no table cache folder: set MESO_CACHE_DIR, XDG_CACHE_HOME or HOME, or pass "
        "--cache-dir");
  std::error_code ec;
  if (std::filesystem::exists(folder, ec) && !std::filesystem::is_directory(folder, ec))
    throw Error(folder.string() + ": the table cache folder is not a folder");
  return folder;
}

// "2024-05-01 12:00:03", local time.
std::string localTime(std::filesystem::file_time_type t) {
  const std::time_t seconds =
      std::chrono::system_clock::to_time_t(std::chrono::file_clock::to_sys(t));
  std::tm parts{};
  localtime_r(&seconds, &parts);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%d %H:%M:%S", &parts);
  return text;
}

std::string tables(int n) { return std::to_string(n) + (n == 1 ? " table" : " tables"); }

}  // namespace

void runCacheList(const CacheCommandOptions& o) {
  const TableCache cache(folderOf(o));
  uint64_t total = 0;
  const std::vector<TableCacheEntry> entries = cache.entries();
  for (const TableCacheEntry& e : entries) {
    std::printf("%s  %10s  %s\n", e.file.filename().string().c_str(),
                formatByteSize(e.bytes).c_str(), localTime(e.lastUse).c_str());
    total += e.bytes;
  }
  std::printf("total: %s, %s (%llu bytes) in %s; limit %s\n",
              tables(static_cast<int>(entries.size())).c_str(), formatByteSize(total).c_str(),
              static_cast<unsigned long long>(total), cache.folder().string().c_str(),
              formatByteSize(cache.limit()).c_str());
}

void runCacheClear(const CacheCommandOptions& o) {
  const TableCache cache(folderOf(o), kDefaultTableCacheLimit);  // the limit plays no part
  const TableCacheRemoval r = cache.clear();
  std::printf("removed %s (%s, %llu bytes) and %d lock files from %s\n", tables(r.removed).c_str(),
              formatByteSize(r.bytesFreed).c_str(), static_cast<unsigned long long>(r.bytesFreed),
              r.locksRemoved, cache.folder().string().c_str());
  if (r.kept > 0)
    std::printf("kept %s (%s): in use by another process or not removable\n",
                tables(r.kept).c_str(), formatByteSize(r.bytesLeft).c_str());
}

void runCachePrune(const CacheCommandOptions& o) {
  const uint64_t limit = o.to.empty() ? TableCache::defaultLimit() : parseByteSize(o.to, "--to");
  const TableCache cache(folderOf(o), limit);
  const TableCacheRemoval r = cache.prune(limit);
  std::printf("removed %s (%s, %llu bytes); %s left in %s (limit %s)\n", tables(r.removed).c_str(),
              formatByteSize(r.bytesFreed).c_str(), static_cast<unsigned long long>(r.bytesFreed),
              formatByteSize(r.bytesLeft).c_str(), cache.folder().string().c_str(),
              formatByteSize(limit).c_str());
  if (r.kept > 0)
    std::printf("kept %s the limit would remove: in use by another process or not removable\n",
                tables(r.kept).c_str());
}

}  // namespace meso::app
