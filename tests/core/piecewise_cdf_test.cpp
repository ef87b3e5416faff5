// The piecewise-linear CDF primitive of the redistribution maps and the synthesis tables:
// cumulative tables, two mixed rows (both roundings), mixtures of up to eight tables, the inverse
// of each forward map on both sides of empty runs, and the inverse of a nondecreasing node
// sequence.
#include "meso/core/piecewise_cdf.h"

#include "meso/core/math.h"
#include "meso/core/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

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
                cdfForward(CdfRows(tables[0]), lo, width, x, shape));
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

// Two rows mix as their RowMix says, bit for bit; one row reads as itself; the two roundings agree
// to float rounding.
TEST(PiecewiseCdf, RowMixRoundsAsStated) {
  Rng rng(5);
  const std::vector<float> a = cumulativeFromMasses(randomMasses(rng, 40));
  const std::vector<float> b = cumulativeFromMasses(randomMasses(rng, 40));
  for (float w : {0.0f, 1e-7f, 0.3f, 0.5f, 0.9999f, 1.0f}) {
    const CdfRows weighted(a, b, w, RowMix::Weighted), lerp(a, b, w, RowMix::Lerp);
    for (size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(lerp.at(i), a[i] + w * (b[i] - a[i]));
      EXPECT_EQ(weighted.at(i), w == 0.0f ? a[i] : (1.0f - w) * a[i] + w * b[i]);
      EXPECT_NEAR(lerp.at(i), weighted.at(i), 2e-7f) << w << " " << i;
      EXPECT_EQ(CdfRows(a).at(i), a[i]);
    }
  }
}

// In bin coordinates, forward and inverse undo each other for one row and for both mixes, on both
// sides, and the forward map is monotone; over [0, n] with unit bins they are the lo/width
// functions bit for bit.
TEST(PiecewiseCdf, BinCoordinatesRoundTrip) {
  Rng rng(11);
  for (int trial = 0; trial < 60; ++trial) {
    const int bins = 2 + trial % 50;
    const std::vector<float> a = cumulativeFromMasses(randomMasses(rng, bins));
    const std::vector<float> b = cumulativeFromMasses(randomMasses(rng, bins));
    const float w = trial % 3 == 0 ? 0.0f : rng.uniform();
    for (const CdfRows& rows :
         {CdfRows(a), CdfRows(a, b, w, RowMix::Weighted), CdfRows(a, b, w, RowMix::Lerp)}) {
      float previous = -1.0f;
      for (int s = 0; s <= 200; ++s) {
        const float t = static_cast<float>(bins) * static_cast<float>(s) / 200.0f;
        const float f = cdfForwardInBins(rows, t);
        EXPECT_GE(f, previous);
        previous = f;
        if (rows.mix == RowMix::Weighted && t > 0.0f && t < static_cast<float>(bins)) {
          EXPECT_EQ(f, cdfForward(rows, 0.0f, 1.0f, t)) << trial << " " << t;
        }
      }
      for (int s = 0; s <= 100; ++s) {
        const float p = static_cast<float>(s) / 100.0f;
        for (InverseSide side : {InverseSide::Lower, InverseSide::Upper}) {
          const BinPosition x = cdfInverseInBins(rows, p, side);
          ASSERT_LT(x.bin, static_cast<size_t>(bins));
          EXPECT_GE(x.fraction, 0.0f);
          EXPECT_LE(x.fraction, 1.0f);
          if (p < 1.0f || side == InverseSide::Upper) {  // (a Weighted mix may end below 1)
            EXPECT_GT(rows.at(x.bin + 1), rows.at(x.bin)) << "the bin has mass";
          }
          EXPECT_NEAR(cdfForwardInBins(rows, x.t()), p, 2e-6f) << trial << " " << p;
        }
        if (p > rows.at(0)) {
          EXPECT_EQ(cdfInverseInBins(rows, p, InverseSide::Lower).t(),
                    cdfInverse(rows, 0.0f, 1.0f, p));
        }
      }
    }
  }
}

// Where F is flat (empty bins, and ahead of and beyond the support) Lower gives the smallest t and
// Upper the largest, and both stay inside the support; p and t outside their ranges clamp.
TEST(PiecewiseCdf, InverseSidesAtEmptyRunsAndEnds) {
  // Mass in bins 1 and 4 of 6: C = 0, 0, 1/2, 1/2, 1/2, 1, 1.
  const std::vector<float> c = cumulativeFromMasses(std::vector<float>{0, 1, 0, 0, 1, 0});
  ASSERT_EQ(c, (std::vector<float>{0.0f, 0.0f, 0.5f, 0.5f, 0.5f, 1.0f, 1.0f}));
  const CdfRows rows(c);
  const auto at = [&](float p, InverseSide side) { return cdfInverseInBins(rows, p, side).t(); };
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (InverseSide side : {InverseSide::Lower, InverseSide::Upper}) {
    EXPECT_EQ(at(0.0f, side), 1.0f);  // the left end of the support, not 0
    EXPECT_EQ(at(-3.0f, side), 1.0f);
    EXPECT_EQ(at(nan, side), 1.0f);
    EXPECT_EQ(at(1.0f, side), 5.0f);  // the right end, not 6
    EXPECT_EQ(at(7.0f, side), 5.0f);
    EXPECT_EQ(at(0.25f, side), 1.5f);
    EXPECT_EQ(at(0.75f, side), 4.5f);
  }
  EXPECT_EQ(at(0.5f, InverseSide::Lower), 2.0f);
  EXPECT_EQ(at(0.5f, InverseSide::Upper), 4.0f);
  const BinPosition lower = cdfInverseInBins(rows, 0.5f, InverseSide::Lower);
  const BinPosition upper = cdfInverseInBins(rows, 0.5f, InverseSide::Upper);
  EXPECT_EQ(lower.bin, 1u);
  EXPECT_EQ(lower.fraction, 1.0f);
  EXPECT_EQ(upper.bin, 4u);
  EXPECT_EQ(upper.fraction, 0.0f);
  EXPECT_EQ(cdfForwardInBins(rows, -1.0f), 0.0f);
  EXPECT_EQ(cdfForwardInBins(rows, nan), 0.0f);
  EXPECT_EQ(cdfForwardInBins(rows, 3.0f), 0.5f);
  EXPECT_EQ(cdfForwardInBins(rows, 6.0f), 1.0f);
  EXPECT_EQ(cdfForwardInBins(rows, 1e9f), 1.0f);
}

// Masses given in double cumulate to the same floats as in float (when they are floats).
TEST(PiecewiseCdf, CumulativeOfDoubleMassesMatchesFloat) {
  Rng rng(23);
  for (int trial = 0; trial < 30; ++trial) {
    const std::vector<float> m =
        trial == 0 ? std::vector<float>(5, 0.0f) : randomMasses(rng, 1 + trial % 20);
    const std::vector<double> md(m.begin(), m.end());
    std::vector<float> fromDouble;
    appendCumulative(std::span<const double>(md), fromDouble);
    EXPECT_EQ(fromDouble, cumulativeFromMasses(m)) << trial;
  }
}

// A nondecreasing node sequence is inverted to the first position it reaches v (flat runs: their
// start), clamped to the ends; linear between nodes.
TEST(PiecewiseCdf, InverseOfANondecreasingSequence) {
  const std::vector<float> y{-2.0f, -1.0f, -1.0f, 0.5f, 3.0f};
  const auto at = [&](int i) { return y[static_cast<size_t>(i)]; };
  EXPECT_EQ(inverseNondecreasing(at, 5, -5.0f), 0.0f);
  EXPECT_EQ(inverseNondecreasing(at, 5, -2.0f), 0.0f);
  EXPECT_EQ(inverseNondecreasing(at, 5, -1.5f), 0.5f);
  EXPECT_EQ(inverseNondecreasing(at, 5, -1.0f), 1.0f);
  EXPECT_EQ(inverseNondecreasing(at, 5, -0.25f), 2.5f);
  EXPECT_EQ(inverseNondecreasing(at, 5, 3.0f), 4.0f);
  EXPECT_EQ(inverseNondecreasing(at, 5, 9.0f), 4.0f);
  Rng rng(29);
  std::vector<float> z(300);
  float v = -1.0f;
  for (float& x : z) x = v += rng.uniform() < 0.1f ? 0.0f : 0.01f + rng.uniform();
  const auto zAt = [&](int i) { return z[static_cast<size_t>(i)]; };
  for (int s = 0; s < 500; ++s) {
    const float t = 299.0f * rng.uniform();
    const int i = std::min(static_cast<int>(t), 298);
    const float value = z[i] + (t - static_cast<float>(i)) * (z[i + 1] - z[i]);
    const float back = inverseNondecreasing(zAt, 300, value);
    const int j = std::min(static_cast<int>(back), 298);
    EXPECT_NEAR(z[j] + (back - static_cast<float>(j)) * (z[j + 1] - z[j]), value, 1e-4f) << t;
    EXPECT_LE(back, t + 1e-2f);
  }
}

}  // namespace
}  // namespace meso
