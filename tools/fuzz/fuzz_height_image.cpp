// libFuzzer target: the height-image loader (OpenImageIO decoding plus meso's checks) must turn any
// bytes into a HeightTable or a meso::Error. The first byte picks the file extension, so the PNG,
// EXR, TIFF and PGM readers are all reached. Build and run with tools/fuzz/run.
#include "meso/core/error.h"
#include "meso/relief/height_source.h"

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* kExtensions[] = {".png", ".exr", ".tif", ".pgm"};
  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("meso_fuzz_height_" + std::to_string(::getpid()) + kExtensions[data[0] % 4]);
  {
    std::ofstream out(file, std::ios::binary);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  try {
    const meso::HeightTable t = meso::HeightTable::load(file);
    (void)t.gradient({0.3f, 0.7f});
  } catch (const meso::Error&) {
  }
  std::filesystem::remove(file);
  return 0;
}
