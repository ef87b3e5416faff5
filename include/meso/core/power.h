// Powers of many values at once, for the table builders' highlight terms.
#pragma once

#include <cmath>
#include <span>

namespace meso {

// Whether raiseToPower takes e by repeated squaring (a whole number from 1 to 65536).
inline bool isWholePower(float e) { return e >= 1.0f && e <= 65536.0f && e == std::floor(e); }

// x[q] = x[q]^e for x in [0, 1]: by repeated squaring in place when e is a whole number (Phong
// exponents usually are; the exact power to about e float roundings, in loops the compiler
// vectorizes: std::pow was a third of the shadowing table's cost), else std::pow. No cutoff for
// small values: where a node's highlight is tiny it still interpolates with the neighbours' that
// are not.
void raiseToPower(std::span<float> x, float e);

}  // namespace meso
