#include "meso/core/power.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace meso {

void raiseToPower(std::span<float> x, float e) {
  const bool whole = e >= 1.0f && e <= 65536.0f && e == std::floor(e);
  if (!whole) {
    for (float& v : x) v = std::pow(v, e);
    return;
  }
  constexpr int kMax = 64;
  float base[kMax], acc[kMax];
  for (size_t q0 = 0; q0 < x.size(); q0 += kMax) {
    const int m = static_cast<int>(std::min(x.size() - q0, static_cast<size_t>(kMax)));
    for (int q = 0; q < m; ++q) base[q] = x[q0 + q], acc[q] = 1.0f;
    for (unsigned bits = static_cast<unsigned>(e); bits != 0; bits >>= 1) {
      if (bits & 1u)
        for (int q = 0; q < m; ++q) acc[q] *= base[q];
      for (int q = 0; q < m; ++q) base[q] *= base[q];
    }
    for (int q = 0; q < m; ++q) x[q0 + q] = acc[q];
  }
}

}  // namespace meso
