// Colour images looked up through OpenImageIO's TextureSystem (MIP-mapped, filtered over a
// footprint), for kd and ks textures (docs/scene-format.md). OpenImageIO stays inside the .cpp.
#pragma once

#include "meso/core/image.h"
#include "meso/core/memory_budget.h"
#include "meso/core/math.h"

#include <cstdint>
#include <filesystem>
#include <memory>

namespace meso {

// How a colour image's values are encoded. Auto: as the file says (OpenImageIO's
// oiio:ColorSpace), else sRGB for integer images and linear for float ones.
enum class ColourSpace { Auto, Srgb, Linear };

// A colour image's texels as linear RGB (channels R, G, B; top row first), and whether its values
// were sRGB-encoded.
struct ColourImage {
  Image rgb;
  bool srgb = false;
};

// Reads `file` (one channel: grey; two: grey and alpha, alpha ignored; more: the first three as
// RGB) and checks it: a readable image of non-zero size whose texels are finite and >= 0. sRGB
// values (as `space` says) are turned linear. Throws meso::Error naming the file; `what` names the
// images in the message ("colour textures hold finite values >= 0"), and (before decoding) for an
// image whose header declares more pixels than memoryLimitBytes holds.
ColourImage readColourImage(const std::filesystem::path& file, ColourSpace space, const char* what,
                            uint64_t memoryLimitBytes = defaultMemoryLimitBytes());

class TextureLookup {
 public:
  TextureLookup();
  ~TextureLookup();
  TextureLookup(const TextureLookup&) = delete;
  TextureLookup& operator=(const TextureLookup&) = delete;

  // Reads and checks `file` (readColourImage) and writes a MIP-mapped, tiled copy under `folder`
  // (named by a hash of the file's bytes and the colour space; written to a temporary name, then
  // renamed) that the TextureSystem reads. Throws meso::Error naming the file. Returns the
  // texture's index.
  int add(const std::filesystem::path& file, ColourSpace space, const std::filesystem::path& folder,
          uint64_t memoryLimitBytes = defaultMemoryLimitBytes());

  // The linear RGB of texture k at (u, v), repeating outside [0, 1)^2 (v = 0 is the image's
  // bottom row, as for height images), filtered over the footprint spanned by (u, v)'s changes
  // per pixel dx and dy (zero: the texel under (u, v), bilinear). Thread-safe.
  Vec3 rgb(int k, Vec2 uv, Vec2 dx, Vec2 dy) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace meso
