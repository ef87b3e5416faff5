#include "meso/core/huge_pages.h"

#include <malloc.h>
#include <sys/mman.h>

#include <cstdint>

namespace meso {

void adviseHugePages(void* p, std::size_t bytes) {
#if defined(MADV_HUGEPAGE)
  const std::uintptr_t size = kHugePageBytes, at = reinterpret_cast<std::uintptr_t>(p);
  if (!p || bytes < size) return;
  const std::uintptr_t begin = (at + size - 1) & ~(size - 1);
  const std::uintptr_t end = (at + bytes) & ~(size - 1);  // at + bytes does not wrap: a real block
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}

void releaseFreedHeap() {
  // Under AddressSanitizer the heap is the sanitizer's, not glibc's arenas.
  if constexpr (kHugeNewBuilt) malloc_trim(kHeapReserveBytes);
}

}  // namespace meso
