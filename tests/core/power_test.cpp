// raiseToPower (power.h): repeated squaring for whole exponents, std::pow otherwise.
#include "meso/core/power.h"

#include "meso/core/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace meso {
namespace {

// Whole exponents from 1 to 65536 and a fractional one, over spans longer and shorter than the
// blocks of the loop and ending inside one: every value is the exact power to float roundings
// (about e of them: each squaring's rounding is raised with the base), 0 and 1 are exact, and a
// fractional exponent is std::pow's exactly.
TEST(Power, WholeExponentsMatchPowAndFractionalOnesArePow) {
  Rng rng(11);
  for (size_t n : {1u, 7u, 256u, 700u})
    for (float e : {1.0f, 2.0f, 3.0f, 20.0f, 40.0f, 127.0f, 1000.0f, 65536.0f, 2.5f}) {
      std::vector<float> x(n);
      for (float& v : x) v = rng.uniform();
      x[0] = 1.0f;
      if (n > 1) x[1] = 0.0f;
      std::vector<float> y = x;
      raiseToPower(y, e);
      for (size_t q = 0; q < n; ++q) {
        const double ref = std::pow(static_cast<double>(x[q]), static_cast<double>(e));
        if (e != std::floor(e)) {
          EXPECT_EQ(y[q], std::pow(x[q], e)) << e << " at " << q;
        } else {
          // A rounding of the base is raised with it: x^(2^k) carries up to (2^k - 1) of them, so
          // x^e up to about e roundings of 2^-24, relative.
          const double tolerance = 2.0 * e * 6e-8 * ref + 1e-30;
          EXPECT_NEAR(y[q], ref, tolerance) << e << " at " << q << " of " << n;
        }
      }
      EXPECT_EQ(y[0], 1.0f);
      if (n > 1) {
        EXPECT_EQ(y[1], 0.0f);
      }
    }
}

}  // namespace
}  // namespace meso
