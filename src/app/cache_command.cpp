#include "cache_command.h"

#include "cli_options.h"
#include "command.h"

#include "meso/appearance/table_cache.h"
#include "meso/core/error.h"

#include <fmt/chrono.h>

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
  return fmt::format("{:%Y-%m-%d %H:%M:%S}", parts);
}

std::string tables(int n) { return std::to_string(n) + (n == 1 ? " table" : " tables"); }

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

// `cache` and its three commands, each with --cache-dir.
class CacheCommand : public Command {
 public:
  explicit CacheCommand(CLI::App& cli) {
    addOptions(cli, options_);
    addMemoryLimit();
  }

 private:
  void addOptions(CLI::App& cli, CacheCommandOptions& o) {
    app_ = cli.add_subcommand(
        "cache", "The table cache folder: list its tables, clear it, or prune it to a size");
    app_->require_subcommand(1);
    const auto addFolder = [&o](CLI::App* sub) {
      addOption(
          sub, "--cache-dir", o.cacheDir,
          "Table cache folder (default $MESO_CACHE_DIR, $XDG_CACHE_HOME/meso or ~/.cache/meso)");
    };
    list_ = app_->add_subcommand(
        "list",
        "One line per table, least recently used first: file, size, last use; then the total");
    addFolder(list_);
    clear_ =
        app_->add_subcommand("clear", "Remove every table and lock file (those in use are kept)");
    addFolder(clear_);
    prune_ = app_->add_subcommand(
        "prune",
        "Remove least recently used tables until the rest fit in a size (the same eviction "
        "that runs after every store)");
    addFolder(prune_);
    addOption(prune_, "--to,--cache-limit", o.to,
              "Size to prune to: bytes with an optional K, M, G or T suffix (500M, 4G); "
              "default $MESO_CACHE_LIMIT, else 4G");
  }

  void execute(const RunContext&) override {
    if (list_->parsed()) runCacheList(options_);
    if (clear_->parsed()) runCacheClear(options_);
    if (prune_->parsed()) runCachePrune(options_);
  }

  CacheCommandOptions options_;
  CLI::App *list_ = nullptr, *clear_ = nullptr, *prune_ = nullptr;
};

}  // namespace

std::unique_ptr<Command> makeCacheCommand(CLI::App& cli) {
  return std::make_unique<CacheCommand>(cli);
}

}  // namespace meso::app
