// Reference renders of `meso trade`, cached on disk (see reference_cache.h).
#include "meso/trade/reference_cache.h"

#include "meso/appearance/table_cache.h"
#include "meso/core/atomic_file.h"
#include "meso/core/cache_file.h"
#include "meso/core/error.h"
#include "meso/core/hash.h"

#include <fmt/format.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>

namespace meso::trade {
namespace {

namespace fs = std::filesystem;

// Bump when the renderer changes what a reference looks like, or the file layout changes.
constexpr uint32_t kFormatVersion =
    6;  // 3: addedMib, 4: reliefSamples, 5: texel cap 8, 6: image bands
constexpr char kMagic[8] = {'M', 'E', 'S', 'O', 'R', 'E', 'F', '1'};

struct Header {
  char magic[8];
  uint32_t version;
  int32_t width, height, frames;
  uint64_t key;
  uint64_t micropolygons;
  double seconds, peakRssMib, geometryMib, addedMib;
};

void hashFile(Hasher& h, const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string() + ": cannot read (for the reference cache key)");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  h.string(file.filename().string()).string(bytes);
}

void hashCamera(Hasher& h, const CameraSettings& c) {
  h.value(c.position).value(c.lookAt).value(c.up).value(c.fovY).value(c.width).value(c.height);
}

uint64_t checksum(const std::vector<std::vector<float>>& frames) {
  Hasher h;
  for (const std::vector<float>& f : frames) h.bytes(f.data(), f.size() * sizeof(float));
  return h.digest();
}

}  // namespace

uint64_t referenceKey(const Scene& scene, const std::vector<CameraSettings>& cameras,
                      float dicingRate, int spp) {
  Hasher h;
  h.value(kFormatVersion);
  hashFile(h, scene.file);
  for (const Object& o : scene.objects) hashFile(h, o.mesh);
  for (const Material& m : scene.materials) {
    for (const ReliefLevelDecl& d : m.relief)
      if (!d.height.empty()) hashFile(h, d.height);
    if (!m.ndf.image.empty()) hashFile(h, m.ndf.image);
  }
  // What the command line may override, and what shapes a full-displacement image.
  const RenderSettings& r = scene.render;
  h.value(dicingRate).value(spp).value(r.seed).value(r.tessellationRate).value(r.background);
  h.string(choiceName(r.dicingMetric)).string(choiceName(r.normals)).value(r.maxMicropolygons);
  h.value(r.reliefSamples);
  h.value(cameras.size());
  for (const CameraSettings& c : cameras) hashCamera(h, c);
  return h.digest();
}

fs::path ReferenceCache::defaultFolder(const Scene& scene) {
  const fs::path base =
      scene.render.cacheDir.empty() ? TableCache::defaultFolder() : scene.render.cacheDir;
  return base.empty() ? fs::path() : base / "references";
}

fs::path ReferenceCache::fileFor(uint64_t key) const {
  return folder_ / fmt::format("{:016x}.ref", key);
}

std::optional<ReferenceRender> ReferenceCache::load(uint64_t key, std::string* warning) const {
  if (folder_.empty()) return std::nullopt;
  CacheFileReader in(fileFor(key), "re-rendering the reference", warning);
  if (!in.opened()) return std::nullopt;
  Header h{};
  if (!in.readHeader(h)) return std::nullopt;
  if (std::memcmp(h.magic, kMagic, sizeof kMagic) != 0 || h.version != kFormatVersion)
    return in.reject("not a meso reference file of this version");
  if (h.key != key) return in.reject("key mismatch");
  if (h.width < 1 || h.height < 1 || h.frames < 1 || h.width > 16384 || h.height > 16384 ||
      h.frames > 100000)
    return in.reject("implausible size");
  ReferenceRender r;
  r.width = h.width, r.height = h.height;
  r.seconds = h.seconds, r.peakRssMib = h.peakRssMib, r.geometryMib = h.geometryMib;
  r.addedMib = h.addedMib;
  r.micropolygons = h.micropolygons;
  const size_t n = static_cast<size_t>(h.width) * static_cast<size_t>(h.height) * 4;
  r.frames.assign(static_cast<size_t>(h.frames), std::vector<float>(n));
  for (std::vector<float>& f : r.frames)
    if (!in.read(f.data(), n * sizeof(float), "truncated pixels")) return std::nullopt;
  uint64_t sum = 0;
  if (!in.read(&sum, sizeof sum, "checksum mismatch")) return std::nullopt;
  if (sum != checksum(r.frames)) return in.reject("checksum mismatch");
  if (!in.atEnd()) return std::nullopt;
  return r;
}

void ReferenceCache::store(uint64_t key, const ReferenceRender& r) const {
  if (folder_.empty()) return;
  std::error_code ec;
  fs::create_directories(folder_, ec);
  if (ec)
    throw Error(folder_.string() + ": cannot create the reference cache folder: " + ec.message());
  const fs::path file = fileFor(key);
  // Built in memory and written by atomic_file, which checks every write, the fsync and the close.
  std::string out;
  const auto append = [&out](const void* p, size_t n) {
    out.append(static_cast<const char*>(p), n);
  };
  Header h{};
  std::memcpy(h.magic, kMagic, sizeof kMagic);
  h.version = kFormatVersion;
  h.width = r.width, h.height = r.height, h.frames = static_cast<int32_t>(r.frames.size());
  h.key = key;
  h.micropolygons = r.micropolygons;
  h.seconds = r.seconds, h.peakRssMib = r.peakRssMib, h.geometryMib = r.geometryMib;
  h.addedMib = r.addedMib;
  append(&h, sizeof h);
  for (const std::vector<float>& f : r.frames) append(f.data(), f.size() * sizeof(float));
  const uint64_t sum = checksum(r.frames);
  append(&sum, sizeof sum);
  writeFileAtomically(file, out);
}

}  // namespace meso::trade
