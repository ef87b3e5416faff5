// libFuzzer target: the OBJ, PLY and OFF readers (meso's text checks, then OpenMesh) must turn any
// bytes into a ControlMesh or a meso::Error, never crash, hang, read out of bounds or allocate
// gigabytes (an OFF face of -5 vertices once made OpenMesh reserve 4 GB). The first byte picks the
// format; the rest is the file. Build with tools/fuzz/run (clang, -fsanitize=fuzzer,address).
#include "meso/core/error.h"
#include "meso/scene/mesh_io.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* const kNames[] = {"fuzz.obj", "fuzz.off", "fuzz.ply"};
  const std::string_view bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    meso::parseControlMesh(bytes, kNames[data[0] % 3]);
  } catch (const meso::Error&) {
  }
  return 0;
}
