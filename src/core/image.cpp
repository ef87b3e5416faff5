#include "meso/core/image.h"

#include <cmath>

namespace meso {

bool Image::allFinite() const {
  for (float v : pixels)
    if (!std::isfinite(v)) return false;
  return true;
}

}  // namespace meso
