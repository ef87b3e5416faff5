#include "meso/core/atomic_file.h"

#include <atomic>
#include <string>
#include <system_error>

#include <unistd.h>

namespace meso {

std::filesystem::path temporarySibling(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  std::string name = "." + target.stem().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                     std::to_string(counter.fetch_add(1)) + target.extension().string();
  return target.parent_path() / name;
}

void writeAtomically(const std::filesystem::path& target,
                     const std::function<void(const std::filesystem::path&)>& write) {
  const std::filesystem::path tmp = temporarySibling(target);
  try {
    write(tmp);
    std::filesystem::rename(tmp, target);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw;
  }
}

}  // namespace meso
