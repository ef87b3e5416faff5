#include "meso/core/huge_pages.h"

#include <malloc.h>
#include <sys/mman.h>

#include <tbb/parallel_for.h>

#include <algorithm>
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

void populatePages(void* p, std::size_t bytes) {
#if defined(MADV_POPULATE_WRITE)
  constexpr std::uintptr_t kPage = 4096;
  // Pieces small enough that both cores get work, large enough that a call maps whole huge pages.
  constexpr std::uintptr_t kPiece = kHugePageBytes;
  if (!p || bytes < 2 * kPiece) return;  // the first write maps so little on its own
  const std::uintptr_t at = reinterpret_cast<std::uintptr_t>(p);
  // Whole pages inside the block: a page it shares with its neighbours is mapped by their writes.
  const std::uintptr_t begin = (at + kPage - 1) & ~(kPage - 1), end = (at + bytes) & ~(kPage - 1);
  // Pieces on 2 MiB bounds, clipped to the block.
  const std::uintptr_t base = begin & ~(kPiece - 1);
  const std::size_t pieces = (end - base + kPiece - 1) / kPiece;
  tbb::parallel_for(std::size_t(0), pieces, [&](std::size_t k) {
    const std::uintptr_t lo = std::max(begin, base + k * kPiece);
    const std::uintptr_t hi = std::min(end, base + (k + 1) * kPiece);
    if (hi > lo) madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_POPULATE_WRITE);
  });
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
