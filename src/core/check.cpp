// A failed MESO_DCHECK (check.h).
#include "meso/core/check.h"

#include <cstdio>
#include <cstdlib>

namespace meso {

void dcheckFailed(const char* file, int line, const char* condition, const char* message) {
  std::fprintf(stderr, "%s:%d: MESO_DCHECK(%s) failed: %s\n", file, line, condition, message);
  std::fflush(stderr);
  std::abort();
}

}  // namespace meso
