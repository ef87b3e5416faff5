// Decoding an image file held in memory (OpenImageIO through an in-memory IOProxy): for data that
// never was a file, and for fuzzing the decoders without touching the file system.
#pragma once

#include "meso/core/image.h"
#include "meso/core/memory_budget.h"

#include <cstddef>
#include <filesystem>

namespace meso {

// Decodes `size` bytes as the format named by `name`'s extension (.png, .exr, .tif, .pgm, ...), all
// channels, as float. Only that format's reader is tried: no probing of other formats and no file
// access. Throws meso::Error("NAME: ...") for an unknown extension, a reader that cannot read from
// memory, bytes that are not a valid image of that format, or (before allocating anything for
// pixels) an image of more than `maxValues` channel values (0: OpenImageIO's limits:imagesize_MB
// alone, as for files) or of more than memoryLimitBytes.
Image readImageFromMemory(const void* data, size_t size, const std::filesystem::path& name,
                          size_t maxValues = 0,
                          uint64_t memoryLimitBytes = defaultMemoryLimitBytes());

}  // namespace meso
