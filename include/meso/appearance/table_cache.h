// The on-disk cache of appearance tables (DESIGN.md section 4): one file per key, verified on load;
// a stale, truncated or corrupt file is rebuilt, never trusted. Processes sharing a folder build a
// key once (a flock(2) per key), and the folder is held under a size limit by evicting the least
// recently used tables.
#pragma once

#include "meso/core/hash.h"
#include "meso/core/warnings.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace meso {

// Bump this whenever the layout or meaning of any cached table changes: old files become misses.
inline constexpr uint32_t kTableFormatVersion =
    5;  // 4: masses only, view-azimuth slices, word checksum; 5: BRDF theta_L to pi

// The size limit of a cache folder unless $MESO_CACHE_LIMIT says otherwise.
inline constexpr uint64_t kDefaultTableCacheLimit = uint64_t{4} << 30;

// Bytes from "1234", "500K", "500M" or "4G" (binary multiples, suffix in either case, an optional
// trailing B or iB: "4GiB"); throws meso::Error("WHAT: expected ...") on anything else or on
// overflow. `what` names where the text came from (MESO_CACHE_LIMIT, --to).
uint64_t parseByteSize(std::string_view text, const std::string& what);
// "512 B", "3.2 MiB", "4.0 GiB".
std::string formatByteSize(uint64_t bytes);

// One table in a cache folder.
struct TableCacheEntry {
  std::filesystem::path file;
  uint64_t key = 0;
  uint64_t bytes = 0;
  std::filesystem::file_time_type lastUse;  // the file's mtime: load() touches it on a hit
};

// What prune() or clear() did.
struct TableCacheRemoval {
  int removed = 0;          // tables deleted
  uint64_t bytesFreed = 0;  // their size
  int kept = 0;             // tables left: their lock is held elsewhere, or removing failed
  int locksRemoved = 0;     // lock files deleted (clear() only)
  uint64_t bytesLeft = 0;   // the tables that remain
};

class TableCache {
 public:
  // A key's build lock, held until destroyed or unlock(): flock(LOCK_EX) on <key>.lock beside the
  // table. Locks are per open file description, so two TableCache objects of one process exclude
  // each other like two processes do. An empty Lock (disabled cache, unwritable folder) holds
  // nothing.
  class Lock {
   public:
    Lock() = default;
    Lock(Lock&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
    Lock& operator=(Lock&& other) noexcept;
    Lock(const Lock&) = delete;
    Lock& operator=(const Lock&) = delete;
    ~Lock() { unlock(); }
    bool held() const { return fd_ >= 0; }
    void unlock();

   private:
    friend class TableCache;
    explicit Lock(int fd) : fd_(fd) {}
    int fd_ = -1;
  };

  // An empty folder disables the cache (every load misses, store does nothing). The limit is
  // defaultLimit(), read only for a non-empty folder.
  explicit TableCache(std::filesystem::path folder);
  TableCache(std::filesystem::path folder, uint64_t limitBytes);
  // $MESO_CACHE_DIR, else $XDG_CACHE_HOME/meso, else $HOME/.cache/meso, else none.
  static std::filesystem::path defaultFolder();
  // $MESO_CACHE_LIMIT (parseByteSize; a bad value throws meso::Error naming the variable), else
  // kDefaultTableCacheLimit.
  static uint64_t defaultLimit();

  const std::filesystem::path& folder() const { return folder_; }
  uint64_t limit() const { return limit_; }
  std::filesystem::path fileFor(uint64_t key) const;
  std::filesystem::path lockFileFor(uint64_t key) const;
  // The cached floats, or nullopt on a miss. A hit sets the file's mtime to now (its last use, for
  // eviction). A file that exists but fails a check (magic, version, key, size, checksum) is
  // deleted and *warning says why, so the caller rebuilds it.
  std::optional<std::vector<float>> load(uint64_t key, std::string* warning) const;
  // Writes atomically (temporary file, then rename), then evicts least recently used tables other
  // than this one while the folder's tables exceed limit(). Failure to write is only a warning.
  void store(uint64_t key, std::span<const float> data, std::string* warning) const;

  // Blocks until this key's build lock is held (see Lock).
  Lock lock(uint64_t key) const;
  // load(); on a miss, waits for the key's lock into *lock and loads again, since another process
  // may have stored the table meanwhile. On a second miss the caller builds and stores the table,
  // then releases *lock: processes that share the folder build each key once.
  std::optional<std::vector<float>> loadOrLock(uint64_t key, std::string* warning,
                                               Lock* lock) const;
  // loadOrLock(), then on a miss build() and store() under the lock. *built says whether build()
  // ran; problems (a rejected file, a failed write) are added to *warnings (may be null).
  std::vector<float> loadOrBuild(uint64_t key, const std::function<std::vector<float>()>& build,
                                 Warnings* warnings, bool* built = nullptr) const;

  // The tables in the folder (files named <16 hex digits>.tbl; subfolders such as references/ and
  // temporaries are not tables), least recently used first. Throws meso::Error when the folder
  // exists and cannot be read; a missing folder has none.
  std::vector<TableCacheEntry> entries() const;
  // Deletes least recently used tables until the rest take at most limitBytes, never `keep` and
  // never a table whose lock another process or object holds.
  TableCacheRemoval prune(uint64_t limitBytes, std::optional<uint64_t> keep = std::nullopt) const;
  // Deletes every table and lock file that no one holds.
  TableCacheRemoval clear() const;

 private:
  // The lock in `file` without waiting: false when someone holds it; else true, with *lock holding
  // it, or nothing when the file cannot be opened (a missing lock file is held by no one).
  static bool tryLockFile(const std::filesystem::path& file, Lock* lock);

  std::filesystem::path folder_;
  uint64_t limit_ = kDefaultTableCacheLimit;
};

}  // namespace meso
