#include "meso/core/power.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace meso {

void raiseToPower(std::span<float> x, float e) {
  if (!isWholePower(e)) {
    for (float& v : x) v = std::pow(v, e);
    return;
  }
  raiseToWholePower(x.data(), x.size(), static_cast<unsigned>(e));
}

}  // namespace meso
