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
  // Repeated squaring in place: x holds the base, acc the product of the powers taken so far, one
  // pass over a block per bit of e (the last squaring is skipped).
  constexpr size_t kBlock = 256;
  float acc[kBlock];
  const unsigned bits0 = static_cast<unsigned>(e);
  for (size_t q0 = 0; q0 < x.size(); q0 += kBlock) {
    const size_t m = std::min(x.size() - q0, kBlock);
    float* base = x.data() + q0;
    bool first = true;
    for (unsigned bits = bits0;;) {
      if (bits & 1u) {
        if (first)
          for (size_t q = 0; q < m; ++q) acc[q] = base[q];
        else
          for (size_t q = 0; q < m; ++q) acc[q] *= base[q];
        first = false;
      }
      bits >>= 1;
      if (bits == 0) break;
      for (size_t q = 0; q < m; ++q) base[q] *= base[q];
    }
    for (size_t q = 0; q < m; ++q) base[q] = acc[q];
  }
}

}  // namespace meso
