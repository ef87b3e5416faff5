#include "meso/appearance/table_cache.h"

#include "meso/core/atomic_file.h"
#include "meso/core/cache_file.h"
#include "meso/core/error.h"

#include <fmt/format.h>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <system_error>

namespace meso {
namespace fs = std::filesystem;
namespace {

constexpr char kMagic[8] = {'M', 'E', 'S', 'O', 'T', 'B', 'L', '\n'};

struct Header {
  char magic[8];
  uint32_t version;
  uint32_t reserved;
  uint64_t key;
  uint64_t count;     // floats in the payload
  uint64_t checksum;  // FNV-1a of the payload bytes
};

// FNV-1a over 32-bit words (the payload is floats): a quarter of the byte-wise loop's work, which
// dominated loading a table set (about 4 MB each with view-azimuth slices).
uint64_t checksumOf(std::span<const float> data) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (const float f : data) {
    uint32_t w;
    std::memcpy(&w, &f, sizeof w);
    h = (h ^ w) * 0x100000001b3ull;
  }
  return h;
}

std::string keyName(uint64_t key, const char* extension) {
  return fmt::format("{:016x}{}", key, extension);
}

// The key of a file named as keyName() names them, or nullopt (temporaries start with a dot).
std::optional<uint64_t> keyOf(const std::string& name, std::string_view extension) {
  if (name.size() != 16 + extension.size() || !name.ends_with(extension)) return std::nullopt;
  uint64_t key = 0;
  for (size_t i = 0; i < 16; ++i) {
    const char c = name[i];
    const int digit = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
    if (digit < 0) return std::nullopt;
    key = key << 4 | static_cast<uint64_t>(digit);
  }
  return key;
}

// Regular files of `folder` named <key><extension>; a missing folder has none.
std::vector<std::pair<fs::path, uint64_t>> keyedFiles(const fs::path& folder,
                                                      std::string_view extension) {
  std::vector<std::pair<fs::path, uint64_t>> out;
  if (folder.empty()) return out;
  std::error_code ec;
  fs::directory_iterator it(folder, ec);
  if (ec == std::errc::no_such_file_or_directory) return out;
  if (ec) throw Error(folder.string() + ": cannot read the table cache folder: " + ec.message());
  for (; it != fs::directory_iterator(); it.increment(ec)) {
    std::error_code statError;
    if (it->symlink_status(statError).type() != fs::file_type::regular) continue;
    if (const auto key = keyOf(it->path().filename().string(), extension))
      out.emplace_back(it->path(), *key);
  }
  if (ec) throw Error(folder.string() + ": cannot read the table cache folder: " + ec.message());
  return out;
}

}  // namespace

uint64_t parseByteSize(std::string_view text, const std::string& what) {
  const auto bad = [&](const char* problem) {
    return Error(what +
                 ": expected a size in bytes with an optional K, M, G or T suffix (such as " +
                 "500M or 4G), got '" + std::string(text) + "'" + problem);
  };
  constexpr uint64_t kMax = std::numeric_limits<uint64_t>::max();
  uint64_t n = 0;
  size_t i = 0;
  for (; i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i) {
    const uint64_t digit = static_cast<uint64_t>(text[i] - '0');
    if (n > (kMax - digit) / 10) throw bad(" (too large)");
    n = n * 10 + digit;
  }
  if (i == 0) throw bad("");
  std::string suffix;
  for (const char c : text.substr(i)) suffix += static_cast<char>(std::toupper(c));
  int shift = 0;
  if (!suffix.empty()) {
    const size_t at = std::string_view("KMGT").find(suffix[0]);
    if (at != std::string_view::npos) {
      shift = 10 * (static_cast<int>(at) + 1);
      suffix.erase(0, 1);
    }
  }
  if (!(suffix.empty() || suffix == "B" || (shift > 0 && suffix == "IB"))) throw bad("");
  if (shift > 0 && n > (kMax >> shift)) throw bad(" (too large)");
  return n << shift;
}

std::string formatByteSize(uint64_t bytes) {
  if (bytes < 1024) return fmt::format("{} B", bytes);
  constexpr const char* kUnits[] = {"KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  double value = static_cast<double>(bytes) / 1024.0;
  int unit = 0;
  for (; value >= 1024.0 && unit < 5; ++unit) value /= 1024.0;
  return fmt::format("{:.1f} {}", value, kUnits[unit]);
}

TableCache::Lock& TableCache::Lock::operator=(Lock&& other) noexcept {
  if (this != &other) {
    unlock();
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

void TableCache::Lock::unlock() {
  if (fd_ < 0) return;
  ::close(fd_);  // closing the last descriptor of the open file releases its flock
  fd_ = -1;
}

TableCache::TableCache(fs::path folder)
    : folder_(std::move(folder)),
      limit_(folder_.empty() ? kDefaultTableCacheLimit : defaultLimit()) {}

TableCache::TableCache(fs::path folder, uint64_t limitBytes)
    : folder_(std::move(folder)), limit_(limitBytes) {}

fs::path TableCache::defaultFolder() {
  if (const char* d = std::getenv("MESO_CACHE_DIR"); d && *d) return d;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return fs::path(x) / "meso";
  if (const char* h = std::getenv("HOME"); h && *h) return fs::path(h) / ".cache" / "meso";
  return {};
}

uint64_t TableCache::defaultLimit() {
  const char* v = std::getenv("MESO_CACHE_LIMIT");
  return v && *v ? parseByteSize(v, "MESO_CACHE_LIMIT") : kDefaultTableCacheLimit;
}

fs::path TableCache::fileFor(uint64_t key) const { return folder_ / keyName(key, ".tbl"); }

fs::path TableCache::lockFileFor(uint64_t key) const { return folder_ / keyName(key, ".lock"); }

std::optional<std::vector<float>> TableCache::load(uint64_t key, std::string* warning) const {
  if (folder_.empty()) return std::nullopt;
  const fs::path file = fileFor(key);
  CacheFileReader in(file, "rebuilding", warning);
  if (!in.opened()) return std::nullopt;
  Header h{};
  if (!in.readHeader(h)) return std::nullopt;
  if (std::memcmp(h.magic, kMagic, sizeof kMagic) != 0) return in.reject("not a meso table file");
  if (h.version != kTableFormatVersion) return in.reject("stale table format version");
  if (h.key != key) return in.reject("key mismatch");
  if (h.count > (uint64_t{1} << 32)) return in.reject("implausible size");
  std::vector<float> data(h.count);
  if (!in.read(data.data(), h.count * sizeof(float), "truncated payload")) return std::nullopt;
  if (!in.atEnd()) return std::nullopt;
  if (checksumOf(data) != h.checksum) return in.reject("checksum mismatch (corrupt)");
  // The mtime is the last use that eviction goes by; a read-only folder just keeps the old one.
  std::error_code ignored;
  fs::last_write_time(file, fs::file_time_type::clock::now(), ignored);
  return data;
}

void TableCache::store(uint64_t key, std::span<const float> data, std::string* warning) const {
  if (folder_.empty()) return;
  const fs::path file = fileFor(key);
  try {
    fs::create_directories(folder_);
    Header h{};
    std::memcpy(h.magic, kMagic, sizeof kMagic);
    h.version = kTableFormatVersion;
    h.key = key;
    h.count = data.size();
    h.checksum = checksumOf(data);
    writeAtomically(file, [&](const fs::path& tmp) {
      std::ofstream out(tmp, std::ios::binary);
      out.write(reinterpret_cast<const char*>(&h), sizeof h);
      out.write(reinterpret_cast<const char*>(data.data()),
                static_cast<std::streamsize>(data.size_bytes()));
      if (!out.flush()) throw Error(tmp.string() + ": write failed");
    });
  } catch (const std::exception& e) {
    if (warning) *warning = file.string() + ": cannot write table cache (" + e.what() + ")";
    return;
  }
  try {
    prune(limit_, key);
  } catch (const std::exception& e) {
    if (warning) *warning = std::string("cannot evict old tables (") + e.what() + ")";
  }
}

TableCache::Lock TableCache::lock(uint64_t key) const {
  if (folder_.empty()) return {};
  std::error_code ec;
  fs::create_directories(folder_, ec);
  const int fd = ::open(lockFileFor(key).c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return {};  // an unwritable folder: nothing to share a build through
  int status;
  while ((status = ::flock(fd, LOCK_EX)) != 0 && errno == EINTR) {
  }
  if (status != 0) {  // no locks on this filesystem: build without one
    ::close(fd);
    return {};
  }
  return Lock(fd);
}

bool TableCache::tryLockFile(const fs::path& file, Lock* lock) {
  *lock = Lock();
  const int fd = ::open(file.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) return true;
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const bool busy = errno == EWOULDBLOCK;
    ::close(fd);
    return !busy;
  }
  *lock = Lock(fd);
  return true;
}

std::optional<std::vector<float>> TableCache::loadOrLock(uint64_t key, std::string* warning,
                                                         Lock* lock) const {
  std::optional<std::vector<float>> data = load(key, warning);
  if (data || folder_.empty()) return data;
  *lock = this->lock(key);
  std::string again;
  data = load(key, &again);
  if (!again.empty() && warning) *warning = warning->empty() ? again : *warning + "; " + again;
  return data;
}

std::vector<float> TableCache::loadOrBuild(uint64_t key,
                                           const std::function<std::vector<float>()>& build,
                                           Warnings* warnings, bool* built) const {
  Lock held;
  std::string warning;
  std::optional<std::vector<float>> data = loadOrLock(key, &warning, &held);
  if (warnings) warnings->add(warning);
  if (built) *built = !data;
  if (data) return std::move(*data);
  std::vector<float> fresh = build();
  warning.clear();
  store(key, fresh, &warning);
  if (warnings) warnings->add(warning);
  return fresh;
}

std::vector<TableCacheEntry> TableCache::entries() const {
  std::vector<TableCacheEntry> out;
  for (const auto& [file, key] : keyedFiles(folder_, ".tbl")) {
    std::error_code sizeError, timeError;  // a file gone since the listing is left out
    const uint64_t bytes = fs::file_size(file, sizeError);
    const fs::file_time_type lastUse = fs::last_write_time(file, timeError);
    if (!sizeError && !timeError) out.push_back({file, key, bytes, lastUse});
  }
  std::sort(out.begin(), out.end(), [](const TableCacheEntry& a, const TableCacheEntry& b) {
    return a.lastUse != b.lastUse ? a.lastUse < b.lastUse : a.file < b.file;
  });
  return out;
}

TableCacheRemoval TableCache::prune(uint64_t limitBytes, std::optional<uint64_t> keep) const {
  TableCacheRemoval r;
  const std::vector<TableCacheEntry> list = entries();
  for (const TableCacheEntry& e : list) r.bytesLeft += e.bytes;
  for (const TableCacheEntry& e : list) {
    if (r.bytesLeft <= limitBytes) break;
    if (keep && e.key == *keep) continue;
    Lock held;
    if (!tryLockFile(lockFileFor(e.key), &held)) {
      ++r.kept;
      continue;
    }
    std::error_code ec;
    if (!fs::remove(e.file, ec)) continue;
    ++r.removed;
    r.bytesFreed += e.bytes;
    r.bytesLeft -= e.bytes;
  }
  return r;
}

TableCacheRemoval TableCache::clear() const {
  TableCacheRemoval r;
  for (const TableCacheEntry& e : entries()) {
    Lock held;
    std::error_code ec;
    if (tryLockFile(lockFileFor(e.key), &held) && fs::remove(e.file, ec)) {
      ++r.removed;
      r.bytesFreed += e.bytes;
    } else {
      ++r.kept;
      r.bytesLeft += e.bytes;
    }
  }
  // A lock file is removed only while held. A process that opened it before and waits for it then
  // locks a file no longer in the folder, so a build may run twice; the stores stay atomic.
  for (const auto& [file, key] : keyedFiles(folder_, ".lock")) {
    Lock held;
    std::error_code ec;
    if (tryLockFile(file, &held) && fs::remove(file, ec)) ++r.locksRemoved;
  }
  return r;
}

}  // namespace meso
