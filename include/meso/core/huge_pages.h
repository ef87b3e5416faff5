// Transparent huge pages for large buffers. A render first-touches hundreds of MiB (tables,
// micropolygons, Embree's buffers and BVH) and each 4 KiB page costs a page fault; on virtual
// machines, where faults are expensive (about 14 us each on the machine meso is developed on),
// they were a third of a default render's time. Where the kernel's transparent huge pages are in
// `madvise` mode (Debian's default), memory advised before it is first touched is mapped 2 MiB per
// fault. The advice is a hint: nothing changes where the kernel has no huge pages, and the memory
// stays the caller's (freed as it was allocated).
#pragma once

#include <cstddef>

namespace meso {

inline constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

// Advises the whole 2 MiB pages inside [p, p + bytes) (nothing when no whole one lies inside);
// errors are ignored. Call it before the block is first written.
void adviseHugePages(void* p, std::size_t bytes);

// Maps the pages of [p, p + bytes), still untouched, on every core: a fresh block's pages are
// zeroed by the kernel at their first write, and where one thread writes blocks of tens of MiB (a
// vector's resize, a copy) that zeroing was about a fifth of a frame's set-up, on one core. The
// kernel's MADV_POPULATE_WRITE on 2 MiB pieces in parallel, for blocks of 4 MiB or more; nothing
// where the kernel lacks it (the first write then maps them). The contents are not changed.
void populatePages(void* p, std::size_t bytes);

// v.resize(n) for a vector (or string) not yet holding its n elements' storage, its new pages
// mapped by populatePages first (the resize then writes to mapped memory). `room`: elements of
// capacity to reserve beyond n, left unmapped until written.
template <class Container>
void resizePopulated(Container& v, std::size_t n, std::size_t room = 0) {
  if (n + room > v.capacity()) {
    v.reserve(n + room);
    if (n > v.size())
      populatePages(v.data() + v.size(), (n - v.size()) * sizeof(typename Container::value_type));
  }
  v.resize(n);
}

// The meso executable's set-up (src/core/huge_new.cpp): its operator new advises blocks of at least
// kHugeNewMinBytes (smaller ones rarely hold a whole aligned huge page); before main, malloc's heap
// is grown by kHeapReserveBytes of address space advised as huge pages, which malloc keeps, and
// blocks of kHeapMmapBytes or more get mappings of their own.
inline constexpr std::size_t kHugeNewMinBytes = 2 * kHugePageBytes;
// The set-up is left out under AddressSanitizer, which keeps its own operator new and heap (GCC
// says so with __SANITIZE_ADDRESS__, clang with __has_feature). MESO_HUGE_NEW is the switch
// huge_new.cpp is compiled by; kHugeNewBuilt says the same to C++ (the tests).
#if defined(__SANITIZE_ADDRESS__)
#define MESO_HUGE_NEW 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MESO_HUGE_NEW 0
#endif
#endif
#ifndef MESO_HUGE_NEW
#define MESO_HUGE_NEW 1
#endif
inline constexpr bool kHugeNewBuilt = MESO_HUGE_NEW == 1;
inline constexpr std::size_t kHeapReserveBytes = std::size_t{768} << 20;
inline constexpr std::size_t kHeapMmapBytes = std::size_t{32} << 20;

// Gives the whole free pages of malloc's arenas back to the system (malloc_trim), the heap's
// reserve at its top kept. Memory a thread frees stays in its own arena, where other threads'
// blocks do not reuse it: call it after a parallel step whose large temporaries are freed, before
// the next step that allocates much (memory the step would have reused is touched again). Tested
// on the arena of a thread still running, as a pool's workers are.
void releaseFreedHeap();

}  // namespace meso
