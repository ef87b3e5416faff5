// The piecewise-linear CDF primitive of the redistribution tables: cumulative tables, mixtures of
// up to eight of them, and the inverse of each forward map.
#include "meso/appearance/piecewise_cdf.h"

#include "meso/core/math.h"
#include "meso/core/rng.h"

#include <gtest/gtest.h>

#include <cmath>

namespace meso {
namespace {

std::vector<float> randomMasses(Rng& rng, int n) {
  std::vector<float> m(n);
  for (float& v : m) v = rng.uniform() < 0.2f ? 0.0f : rng.uniform();
  return m;
}

TEST(PiecewiseCdf, AppendCumulativeMatchesCumulativeFromMasses) {
  Rng rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    const std::vector<float> m =
        trial == 0 ? std::vector<float>(7, 0.0f) : randomMasses(rng, 1 + trial % 40);
    std::vector<float> out{42.0f};
    appendCumulative(m, out);
    const std::vector<float> ref = cumulativeFromMasses(m);
    ASSERT_EQ(out.size(), ref.size() + 1);
    for (size_t i = 0; i < ref.size(); ++i) EXPECT_EQ(out[i + 1], ref[i]) << trial << " " << i;
    EXPECT_EQ(ref.back(), 1.0f);
  }
}

// The forward map of a mixture is monotone and cdfInverse undoes it wherever the mixture has mass
// (both bin shapes); mixtures of one table equal the two-table functions with w = 0.
TEST(PiecewiseCdf, MixtureRoundTripAndMonotone) {
  Rng rng(9);
  for (BinShape shape : {BinShape::Uniform, BinShape::SolidAngle}) {
    std::vector<std::vector<float>> tables;
    for (int k = 0; k < 8; ++k) tables.push_back(cumulativeFromMasses(randomMasses(rng, 24)));
    const float lo = 0.0f, width = 0.5f * kPi / 24.0f;
    for (int trial = 0; trial < 200; ++trial) {
      CdfMix mix;
      std::vector<float> w(8);
      float sum = 0.0f;
      for (float& x : w) sum += x = rng.uniform();
      for (int k = 0; k < 8; ++k) mix.add(tables[k], w[k] / sum);
      float previous = -1.0f;
      for (int s = 0; s <= 100; ++s) {
        const float x = lo + 24.0f * width * static_cast<float>(s) / 100.0f;
        const float p = cdfForward(mix, lo, width, x, shape);
        EXPECT_GE(p, previous);
        previous = p;
        if (p > 1e-4f && p < 1.0f - 1e-4f) {
          const float back =
              cdfForward(mix, lo, width, cdfInverse(mix, lo, width, p, shape), shape);
          EXPECT_NEAR(back, p, 2e-5f) << trial << " " << s;
        }
      }
    }
    CdfMix one;
    one.add(tables[0], 1.0f);
    for (float x : {0.1f, 0.7f, 1.3f})
      EXPECT_EQ(cdfForward(one, lo, width, x, shape),
                cdfForward(tables[0], tables[0], 0.0f, lo, width, x, shape));
  }
}

// Guides (appendGuide) only bracket cdfInverse's search: with them every inverse is the same float
// as without, for mixtures of 1 to 8 tables with empty runs, steep steps and p at 0, at guide
// boundaries and at the top; the edge cosines (BinCosines) change nothing either.
TEST(PiecewiseCdf, GuidesAndEdgeCosinesGiveTheSameInverse) {
  Rng rng(17);
  for (int bins : {3, 24, 96, 300}) {
    std::vector<std::vector<float>> tables;
    std::vector<uint16_t> guides;
    for (int k = 0; k < 8; ++k) {
      std::vector<float> m = randomMasses(rng, bins);
      if (k == 1) m.assign(static_cast<size_t>(bins), 0.0f), m[bins / 2] = 1.0f;  // one step
      tables.push_back(cumulativeFromMasses(m));
      appendGuide(tables.back(), guides);
    }
    ASSERT_EQ(guides.size(), 8u * (kCdfGuideSize + 1));
    const float width = 0.5f * kPi / static_cast<float>(bins);
    const BinCosines cosines(0.0f, width, static_cast<size_t>(bins));
    for (int trial = 0; trial < 300; ++trial) {
      CdfMix plain, guided;
      const int count = 1 + trial % 8;
      std::vector<float> w(static_cast<size_t>(count));
      float sum = 0.0f;
      for (float& x : w) sum += x = rng.uniform() + (trial % 3 == 0 ? 1e-7f : 0.0f);
      for (int k = 0; k < count; ++k) {
        plain.add(tables[k], w[k] / sum);
        guided.add(tables[k], w[k] / sum, guides.data() + k * (kCdfGuideSize + 1));
      }
      for (int s = 0; s <= 130; ++s) {
        const float p = s < 128 ? static_cast<float>(s) / 128.0f  // every guide boundary
                                : (s == 128 ? rng.uniform() : 1.0f);
        for (BinShape shape : {BinShape::Uniform, BinShape::SolidAngle}) {
          const float a = cdfInverse(plain, 0.0f, width, p, shape);
          EXPECT_EQ(a, cdfInverse(guided, 0.0f, width, p, shape))
              << bins << " " << trial << " " << p;
          EXPECT_EQ(a, cdfInverse(guided, 0.0f, width, p, shape, &cosines));
          const float x = a + 0.3f * width;
          EXPECT_EQ(cdfForward(plain, 0.0f, width, x, shape),
                    cdfForward(plain, 0.0f, width, x, shape, &cosines));
        }
      }
    }
  }
}

}  // namespace
}  // namespace meso
