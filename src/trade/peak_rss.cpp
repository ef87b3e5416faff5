// Resets the peak resident set size (see peak_rss.h).
#include "meso/trade/peak_rss.h"

#include <malloc.h>

#include <fstream>

namespace meso::trade {

bool resetPeakRss() {
  malloc_trim(0);
  std::ofstream clear("/proc/self/clear_refs");
  if (!clear) return false;
  clear << "5";
  clear.flush();
  return static_cast<bool>(clear);
}

}  // namespace meso::trade
