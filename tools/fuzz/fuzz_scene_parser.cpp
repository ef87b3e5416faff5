// libFuzzer target: the TOML scene parser must turn any input into a Scene or a meso::Error, never
// crash, hang or read out of bounds. Build with tools/fuzz/run (clang, -fsanitize=fuzzer,address).
#include "meso/core/error.h"
#include "meso/scene/scene_parser.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    // A folder that exists, so relative paths resolve, and no mesh file in it matches by chance.
    meso::parseScene(text, "/nonexistent-meso-fuzz/scene.toml");
  } catch (const meso::Error&) {
  }
  return 0;
}
