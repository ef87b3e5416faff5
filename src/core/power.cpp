#include "meso/core/power.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace meso {
namespace {

// x[q] = x[q]^e for a whole e >= 1, by repeated squaring in place: x holds the base, acc the
// product of the powers taken so far, one pass over a block per bit of e (the last squaring is
// skipped).
void raiseToWholePower(float* x, size_t n, unsigned e) {
  constexpr size_t kBlock = 256;
  float acc[kBlock];
  for (size_t q0 = 0; q0 < n; q0 += kBlock) {
    const size_t m = std::min(n - q0, kBlock);
    float* base = x + q0;
    bool first = true;
    for (unsigned bits = e;;) {
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

}  // namespace

void raiseToPower(std::span<float> x, float e) {
  if (!isWholePower(e)) {
    for (float& v : x) v = std::pow(v, e);
    return;
  }
  raiseToWholePower(x.data(), x.size(), static_cast<unsigned>(e));
}

}  // namespace meso
