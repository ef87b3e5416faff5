#include "meso/core/memory_budget.h"

#include "meso/core/error.h"

#include <fmt/format.h>

#include <unistd.h>

namespace meso {
uint64_t physicalMemoryBytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), size = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && size > 0 ? static_cast<uint64_t>(pages) * static_cast<uint64_t>(size) : 0;
}

uint64_t defaultMemoryLimitBytes() {
  const uint64_t physical = physicalMemoryBytes();
  return physical > 0 ? physical / 2 : uint64_t(4) << 30;
}

std::string formatMib(double bytes) { return fmt::format("{:.1f} MiB", bytes / (1024.0 * 1024.0)); }

void requireMemoryWithin(uint64_t limit, double bytes, const std::string& where,
                         const std::string& key, const std::string& what) {
  if (bytes <= static_cast<double>(limit)) return;
  std::string message = where.empty() ? "" : where + ": ";
  message.append(key).append(": needs an estimated ").append(formatMib(bytes));
  if (!what.empty()) message.append(" (").append(what).append(")");
  message.append(", more than the memory limit of ").append(formatMib(static_cast<double>(limit)));
  message.append(" (--memory-limit MIB; default half of physical memory)");
  throw Error(message);
}

}  // namespace meso
