// The meso executable's replacement of the global operator new (linked into it alone, as its own
// object: CMakeLists.txt): blocks of kHugeNewMinBytes or more are advised as transparent huge page
// candidates (meso/core/huge_pages.h) before the caller touches them. The memory still comes from
// malloc, as the default operator new's does, so the default operator delete (free) releases it;
// new[], nothrow new and the default aligned forms are unchanged (libstdc++'s new[] and nothrow new
// call this one). Not under AddressSanitizer, which must see its own new and delete as a pair.
#include "meso/core/huge_pages.h"

#include <cstdlib>
#include <new>

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

#endif
