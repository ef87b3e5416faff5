#include "meso/core/rng.h"

#include <gtest/gtest.h>

#include <vector>

namespace meso {
namespace {

TEST(Rng, SameSeedAndStreamGiveSameSequence) {
  Rng a(42, 7), b(42, 7), c(42, 8), d(43, 7);
  int sameC = 0, sameD = 0;
  for (int i = 0; i < 100; ++i) {
    const uint32_t x = a.nextU32();
    EXPECT_EQ(x, b.nextU32());
    sameC += x == c.nextU32();
    sameD += x == d.nextU32();
  }
  EXPECT_LT(sameC, 3);
  EXPECT_LT(sameD, 3);
}

// Chi-square test of uniform() over 64 equal bins: 64000 draws, 63 degrees of freedom;
// the 0.01 critical value is 92.01.
TEST(Rng, UniformPassesChiSquare) {
  Rng rng(1234, 0);
  constexpr int kBins = 64, kDraws = 64000;
  std::vector<int> counts(kBins, 0);
  for (int i = 0; i < kDraws; ++i) {
    const float u = rng.uniform();
    ASSERT_GE(u, 0.0f);
    ASSERT_LT(u, 1.0f);
    counts[static_cast<int>(u * kBins)]++;
  }
  const double expected = static_cast<double>(kDraws) / kBins;
  double chi2 = 0.0;
  for (int c : counts) chi2 += (c - expected) * (c - expected) / expected;
  EXPECT_LT(chi2, 92.01);
}

}  // namespace
}  // namespace meso
