// The one way meso opens an input file (scene, mesh, image): it must be a regular file (not a FIFO,
// which would block, nor a device such as /dev/zero, which never ends) of at most a size limit.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include <sys/types.h>

namespace meso {

// Default size limits of inputs: scenes are text, meshes and images can be large.
// "a folder", "a FIFO", "a symbolic link", ...: what a file of this st_mode is, for messages.
const char* fileTypeName(mode_t mode);

inline constexpr uint64_t kMaxSceneBytes = uint64_t(64) << 20;
inline constexpr uint64_t kMaxMeshBytes = uint64_t(4) << 30;
inline constexpr uint64_t kMaxImageBytes = uint64_t(4) << 30;

// Returns the size of `file`, throwing meso::Error("FILE: what: expected ...") when it does not
// exist, is not a regular file (after following symlinks) or is larger than maxBytes. Never opens
// the file (opening a FIFO blocks).
uint64_t checkInputFile(const std::filesystem::path& file, const std::string& what,
                        uint64_t maxBytes);

// The bytes of `file`, checked as checkInputFile does on the opened descriptor (O_NONBLOCK, so a
// FIFO swapped in after the check cannot block) and read up to maxBytes.
std::string readInputFile(const std::filesystem::path& file, const std::string& what,
                          uint64_t maxBytes);

}  // namespace meso
