// Becker & Max 1993, eq. (10) and section 4.2.
#include "meso/render/transition.h"

#include "meso/core/error.h"

#include <algorithm>
#include <cmath>

namespace meso {

void validateTransitionSettings(const TransitionSettings& s, const char* where) {
  const float all[] = {s.D, s.eps, s.e1, s.e2, s.e3, s.e4};
  for (float v : all)
    if (!std::isfinite(v))
      throw Error(std::string(where) + ": transition settings must be finite numbers");
  if (s.D < 0.0f) throw Error(std::string(where) + ": D must be >= 0");
  if (s.eps < 0.0f) throw Error(std::string(where) + ": eps must be >= 0");
  if (!thresholdsOrdered(s.e1, s.e2, s.e3, s.e4))
    throw Error(std::string(where) + ": thresholds must satisfy " + kThresholdOrder + ", got " +
                std::to_string(s.e1) + ", " + std::to_string(s.e2) + ", " + std::to_string(s.e3) +
                ", " + std::to_string(s.e4));
}

}  // namespace meso
