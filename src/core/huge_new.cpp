// The meso executable's memory set-up (linked into it alone, as an object of its own:
// CMakeLists.txt), for the page faults of meso/core/huge_pages.h:
// - Before main, malloc's main heap is grown once by kHeapReserveBytes, advised as transparent huge
//   pages and handed back to malloc, which keeps it (the trim threshold is above it): the heap's
//   blocks, small ones included, are then first touched 2 MiB per fault instead of 4 KiB. This is
//   address space, not memory: nothing is touched, and peak RSS rose by about 10 MiB (the
//   partly used huge pages). Blocks of kHeapMmapBytes or more still get mappings of their own.
//   Skipped where `ulimit -v` leaves less than eight times the reserve.
// - The global operator new advises blocks of kHugeNewMinBytes or more (mappings of their own, or
//   heap beyond the reserve) before the caller touches them. The memory still comes from malloc,
//   as the default operator new's does, so the default operator delete (free) releases it; new[],
//   nothrow new and the default aligned forms are unchanged (libstdc++'s new[] and nothrow new call
//   this one).
// Not under AddressSanitizer, which must see its own new and delete as a pair and has its own heap.
#include "meso/core/huge_pages.h"

#include <malloc.h>
#include <sys/resource.h>

#include <array>
#include <cstdlib>
#include <new>

#if MESO_HUGE_NEW

void* operator new(std::size_t n) {
  if (n == 0) n = 1;
  for (;;) {
    if (void* p = std::malloc(n)) {
      if (n >= meso::kHugeNewMinBytes) meso::adviseHugePages(p, n);
      return p;
    }
    const std::new_handler handler = std::get_new_handler();
    if (!handler) throw std::bad_alloc();
    handler();
  }
}

namespace {

// Whether the address space may hold the reserve eight times over (a farm's `ulimit -v` must not
// be spent on it).
bool roomForReserve() {
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) != 0) return false;
  return limit.rlim_cur == RLIM_INFINITY || limit.rlim_cur / 8 >= meso::kHeapReserveBytes;
}

bool reserveHugePageHeap() {
  using meso::kHeapReserveBytes;
  if (!roomForReserve()) return false;
  // Fixed thresholds: blocks under kHeapMmapBytes come from the heap, and freed heap stays there.
  mallopt(M_TRIM_THRESHOLD, static_cast<int>(2 * kHeapReserveBytes));
  mallopt(M_MMAP_THRESHOLD, static_cast<int>(meso::kHeapMmapBytes));
  // The heap grows by pieces just under the mmap threshold (mallopt takes none above 32 MiB, and a
  // larger block would be a mapping of its own), advised untouched and freed together: they merge
  // into the heap's free top.
  constexpr std::size_t kPiece = meso::kHeapMmapBytes - meso::kHugePageBytes;
  std::array<void*, kHeapReserveBytes / kPiece + 1> pieces{};
  std::size_t count = 0;
  for (; count < pieces.size() && count * kPiece < kHeapReserveBytes; ++count)
    if (!(pieces[count] = std::malloc(kPiece))) break;
  for (std::size_t k = 0; k < count; ++k) meso::adviseHugePages(pieces[k], kPiece);
  for (std::size_t k = 0; k < count; ++k) std::free(pieces[k]);
  return count > 0;
}

[[maybe_unused]] const bool heapReserved = reserveHugePageHeap();

}  // namespace

#endif
