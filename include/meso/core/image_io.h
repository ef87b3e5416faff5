// Image files through OpenImageIO. Writers never leave a half-written file under the final name.
#pragma once

#include "meso/core/image.h"
#include "meso/core/memory_budget.h"

#include <filesystem>
#include <string>

namespace meso {

// Reads any format OpenImageIO knows, all channels, as float. Throws meso::Error("FILE: ..."), also
// (before decoding) for an image whose header declares more pixels than memoryLimitBytes holds.
Image readImage(const std::filesystem::path& file,
                uint64_t memoryLimitBytes = defaultMemoryLimitBytes());

// The bytes of an OpenEXR file of all channels (float, zip at zlib's fastest level) and of an 8-bit
// sRGB PNG preview of R, G, B: encoded in memory, so that the caller writes (and checks) them with
// atomic_file.h.
std::string encodeExr(const Image& image);
std::string encodePngPreview(const Image& image);

// The threads OpenImageIO and OpenEXR's thread pool (compressing and decompressing EXR blocks)
// may use: `--threads` (0, every core, is their default).
void setImageThreads(int threads);

// Writes all channels to an OpenEXR file (half or float per channel as stored: float here).
void writeExr(const std::filesystem::path& file, const Image& image);

// Writes an 8-bit sRGB PNG preview of channels R, G, B (clamped to [0, 1], gamma-encoded).
void writePngPreview(const std::filesystem::path& file, const Image& image);

}  // namespace meso
