// Powers of many values at once, for the table builders' highlight terms.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>

namespace meso {

// x[q] = x[q]^e for a whole e >= 1, by repeated squaring in place: x holds the base, acc the
// product of the powers taken so far, one pass over a block per bit of e (the last squaring is
// skipped). Inline, so that a caller compiled for wider vectors gets it in them.
inline void raiseToWholePower(float* x, size_t n, unsigned e) {
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

// Whether raiseToPower takes e by repeated squaring (raiseToWholePower).
inline bool isWholePower(float e) { return e >= 1.0f && e <= 65536.0f && e == std::floor(e); }

// x[q] = x[q]^e for x in [0, 1]: by repeated squaring in place when e is a whole number (Phong
// exponents usually are; the exact power to about e float roundings, in loops the compiler
// vectorizes: std::pow was a third of the shadowing table's cost), else std::pow. No cutoff for
// small values: where a node's highlight is tiny it still interpolates with the neighbours' that
// are not.
void raiseToPower(std::span<float> x, float e);

}  // namespace meso
