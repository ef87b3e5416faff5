#include "meso/appearance/table_cache.h"

#include "meso/core/atomic_file.h"
#include "meso/core/error.h"

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <system_error>

namespace meso {
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

}  // namespace

TableCache::TableCache(std::filesystem::path folder) : folder_(std::move(folder)) {}

std::filesystem::path TableCache::defaultFolder() {
  if (const char* d = std::getenv("MESO_CACHE_DIR"); d && *d) return d;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x)
    return std::filesystem::path(x) / "meso";
  if (const char* h = std::getenv("HOME"); h && *h)
    return std::filesystem::path(h) / ".cache" / "meso";
  return {};
}

std::filesystem::path TableCache::fileFor(uint64_t key) const {
  char name[32];
  std::snprintf(name, sizeof name, "%016llx.tbl", static_cast<unsigned long long>(key));
  return folder_ / name;
}

std::optional<std::vector<float>> TableCache::load(uint64_t key, std::string* warning) const {
  if (folder_.empty()) return std::nullopt;
  const std::filesystem::path file = fileFor(key);
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  const auto reject = [&](const char* why) -> std::optional<std::vector<float>> {
    if (warning) *warning = file.string() + ": " + why + "; rebuilding";
    in.close();
    std::error_code ignored;
    std::filesystem::remove(file, ignored);
    return std::nullopt;
  };
  Header h{};
  if (!in.read(reinterpret_cast<char*>(&h), sizeof h)) return reject("truncated header");
  if (std::memcmp(h.magic, kMagic, sizeof kMagic) != 0) return reject("not a meso table file");
  if (h.version != kTableFormatVersion) return reject("stale table format version");
  if (h.key != key) return reject("key mismatch");
  if (h.count > (uint64_t{1} << 32)) return reject("implausible size");
  std::vector<float> data(h.count);
  if (!in.read(reinterpret_cast<char*>(data.data()),
               static_cast<std::streamsize>(h.count * sizeof(float))))
    return reject("truncated payload");
  if (in.peek() != std::char_traits<char>::eof()) return reject("trailing bytes");
  if (checksumOf(data) != h.checksum) return reject("checksum mismatch (corrupt)");
  return data;
}

void TableCache::store(uint64_t key, std::span<const float> data, std::string* warning) const {
  if (folder_.empty()) return;
  const std::filesystem::path file = fileFor(key);
  try {
    std::filesystem::create_directories(folder_);
    Header h{};
    std::memcpy(h.magic, kMagic, sizeof kMagic);
    h.version = kTableFormatVersion;
    h.key = key;
    h.count = data.size();
    h.checksum = checksumOf(data);
    writeAtomically(file, [&](const std::filesystem::path& tmp) {
      std::ofstream out(tmp, std::ios::binary);
      out.write(reinterpret_cast<const char*>(&h), sizeof h);
      out.write(reinterpret_cast<const char*>(data.data()),
                static_cast<std::streamsize>(data.size_bytes()));
      if (!out.flush()) throw Error(tmp.string() + ": write failed");
    });
  } catch (const std::exception& e) {
    if (warning) *warning = file.string() + ": cannot write table cache (" + e.what() + ")";
  }
}

}  // namespace meso
