// Output files appear under their final name only when complete: write a temporary, then rename.
#pragma once

#include <filesystem>
#include <functional>

namespace meso {

// A temporary name in the same folder as `target` (so rename is atomic), keeping its extension so
// format-sniffing writers pick the right format: "dir/.name.tmp-PID-N.ext".
std::filesystem::path temporarySibling(const std::filesystem::path& target);

// Calls write(tmp) and renames tmp to target; on any exception removes tmp and rethrows.
void writeAtomically(const std::filesystem::path& target,
                     const std::function<void(const std::filesystem::path&)>& write);

}  // namespace meso
