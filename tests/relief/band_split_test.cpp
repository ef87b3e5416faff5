// Becker & Max 1993, section 4.3: band-limited levels of one height map.
#include "meso/relief/band_split.h"
#include "meso/core/error.h"
#include "meso/core/rng.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace meso {
namespace {

// Sinusoids at 2, 9 and 40 cycles per tile plus a little noise, on a non-power-of-two grid.
HeightTable mixture(int w, int h, bool periodic) {
  Rng rng(4);
  std::vector<float> t(static_cast<size_t>(w) * h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const float x = (i + 0.5f) / w, y = (j + 0.5f) / h;
      t[static_cast<size_t>(j) * w + i] = 3.0f + std::sin(2 * kPi * 2 * x) +
                                          0.5f * std::cos(2 * kPi * (9 * y + 0.2f)) +
                                          0.2f * std::sin(2 * kPi * 40 * x) + 0.01f * rng.uniform();
    }
  return HeightTable(w, h, std::move(t), HeightTableOptions{periodic});
}

TEST(BandSplit, BandsSumBackToTheOriginal) {
  for (const auto& [w, h, periodic, levels] :
       {std::tuple{128, 96, true, 3}, std::tuple{100, 60, false, 2}, std::tuple{64, 64, true, 4},
        std::tuple{32, 32, true, 1}}) {
    const HeightTable t = mixture(w, h, periodic);
    const std::vector<HeightBand> bands = splitBands(t, levels);
    ASSERT_EQ(static_cast<int>(bands.size()), levels);
    const auto [lo, hi] = std::minmax_element(t.texels().begin(), t.texels().end());
    const double range = *hi - *lo;
    double worst = 0.0;
    for (size_t k = 0; k < t.texels().size(); ++k) {
      double sum = 0.0;
      for (const HeightBand& b : bands) sum += b.table.texels()[k];
      worst = std::max(worst, std::abs(sum - t.texels()[k]));
    }
    EXPECT_LE(worst, 1e-5 * range) << w << "x" << h << " levels " << levels;
    for (size_t m = 0; m < bands.size(); ++m) {
      EXPECT_EQ(bands[m].table.width(), w);
      EXPECT_EQ(bands[m].table.periodic(), periodic);
      EXPECT_EQ(bands[m].freq, bands[m].table.highestFrequency());
      if (m > 0) {
        EXPECT_GE(bands[m].freq, bands[m - 1].freq) << "low to high";
        // Compact: nothing beyond half an octave past the crossover (the Hann window of the
        // estimate for clamped tables smears lines by a few bins).
        EXPECT_LE(bands[m - 1].freq,
                  std::sqrt(2.0f) * bands[m - 1].highCut + (periodic ? 1.0f : 4.0f));
        EXPECT_EQ(bands[m].lowCut, bands[m - 1].highCut);
      }
    }
  }
}

// Two levels of a 128 x 128 table split at 8 cycles per tile (sqrt(64)): the 2-cycle wave is in the
// low band only, the 9-cycle wave (in the transition) in both, the 40-cycle wave in the high one.
TEST(BandSplit, SeparatesFrequencies) {
  const std::vector<HeightBand> bands = splitBands(mixture(128, 128, true), 2);
  EXPECT_FLOAT_EQ(bands[0].highCut, 8.0f);
  EXPECT_GE(bands[0].freq, 9.0f);
  EXPECT_LE(bands[0].freq, 8.0f * std::sqrt(2.0f));
  EXPECT_GE(bands[1].freq, 40.0f);
  // The low band holds the mean; the high band has (almost) none.
  double meanLow = 0.0, meanHigh = 0.0;
  for (float v : bands[0].table.texels()) meanLow += v;
  for (float v : bands[1].table.texels()) meanHigh += v;
  EXPECT_NEAR(meanLow / (128 * 128), 3.0, 0.01);
  EXPECT_NEAR(meanHigh / (128 * 128), 0.0, 1e-4);
}

TEST(BandSplit, RejectsBadLevelCounts) {
  const HeightTable t = mixture(8, 8, true);
  EXPECT_THROW(splitBands(t, 0), Error);
  EXPECT_THROW(splitBands(t, 17), Error);
}

// Each band at least an octave wide: floor(log2(min(W, H) / 2)) bands, at least one; more are
// refused, as many are split with increasing crossovers.
TEST(BandSplit, BandsAreAtLeastAnOctaveWide) {
  for (const auto& [w, h, most] : {std::tuple{1, 1, 1}, std::tuple{4, 4, 1}, std::tuple{8, 8, 2},
                                   std::tuple{17, 16, 3}, std::tuple{128, 96, 5}}) {
    const HeightTable t = mixture(w, h, true);
    EXPECT_EQ(maxBandLevels(t), most) << w << "x" << h;
    EXPECT_THROW(splitBands(t, most + 1), Error) << w << "x" << h;
    const std::vector<HeightBand> bands = splitBands(t, most);
    ASSERT_EQ(static_cast<int>(bands.size()), most);
    for (size_t m = 1; m < bands.size(); ++m)
      EXPECT_GE(bands[m].highCut, 2.0f * bands[m].lowCut * (1.0f - 1e-5f)) << w << "x" << h;
  }
}

}  // namespace
}  // namespace meso

namespace meso {
namespace {

// Sinusoids of given (cycles per tile, amplitude) along x, on a periodic 128 x 128 table.
HeightTable waves(std::initializer_list<std::pair<float, float>> parts) {
  const int n = 128;
  std::vector<float> t(static_cast<size_t>(n) * n, 0.0f);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      for (const auto& [f, a] : parts)
        t[static_cast<size_t>(j) * n + i] += a * std::sin(2 * kPi * f * (i + 0.5f) / n);
  return HeightTable(n, n, std::move(t), HeightTableOptions{true});
}

// The default plan of a height image: as many octave bands as it holds, the levels cover every
// band once, coarse to fine, their tables sum back to the image, and their shares sum to 1 (with
// no minimum share, only bands of one frequency or of correlated slopes are merged).
TEST(BandPlan, LevelsCoverEveryBandOnceAndSumBack) {
  const HeightTable t = mixture(128, 128, true);
  const BandPlan plan = planBands(t, 0, 8, 0.0);
  EXPECT_EQ(plan.bands, maxBandLevels(t));
  ASSERT_GE(plan.levels.size(), 2u);
  EXPECT_EQ(plan.levels.front().first, 0);
  EXPECT_EQ(plan.levels.back().last, plan.bands - 1);
  double shares = 0.0;
  std::vector<double> sum(t.texels().size(), 0.0);
  for (size_t k = 0; k < plan.levels.size(); ++k) {
    if (k > 0) {
      EXPECT_EQ(plan.levels[k].first, plan.levels[k - 1].last + 1);
    }
    EXPECT_LE(plan.levels[k].first, plan.levels[k].last);
    shares += plan.levels[k].slopeShare;
    const HeightTable level =
        bandLevelTable(t, plan.bands, plan.levels[k].first, plan.levels[k].last);
    for (size_t i = 0; i < sum.size(); ++i) sum[i] += level.texels()[i];
  }
  EXPECT_NEAR(shares, 1.0, 1e-9);
  double worst = 0.0;
  for (size_t i = 0; i < sum.size(); ++i) worst = std::max(worst, std::abs(sum[i] - t.texels()[i]));
  EXPECT_LT(worst, 1e-4);
}

// A strong wave at 20 cycles and a weak one at 3 (slope share (3 * 0.02)^2 / ... ~ 1e-3): the
// weak band joins its finer neighbour and the level that carries the slope keeps it; a wave of
// equal slope at 3 cycles (amplitude 20/3 times larger) stays a level of its own.
TEST(BandPlan, WeakBandsJoinTheirFinerNeighbour) {
  const BandPlan weak = planBands(waves({{20.0f, 0.1f}, {3.0f, 0.01f}}), 0, 8);
  for (const BandLevel& l : weak.levels) EXPECT_GE(l.slopeShare, kMinBandSlopeShare);
  ASSERT_GE(weak.levels.size(), 1u);
  EXPECT_EQ(weak.levels.front().first, 0);
  EXPECT_EQ(weak.levels.back().last, weak.bands - 1);
  // Every band is in exactly one level, in order.
  for (size_t k = 1; k < weak.levels.size(); ++k)
    EXPECT_EQ(weak.levels[k].first, weak.levels[k - 1].last + 1);
  // The 3-cycle wave is in the same level as the 20-cycle one.
  const auto levelOf = [](const BandPlan& p, float f) {
    const int n = p.bands;
    const double nyquist = 64.0;
    // band m (0-based) spans edges nyquist^(m / n) .. nyquist^((m + 1) / n)
    int band = 0;
    while (band + 1 < n && f > std::pow(nyquist, static_cast<double>(band + 1) / n)) ++band;
    for (size_t k = 0; k < p.levels.size(); ++k)
      if (band >= p.levels[k].first && band <= p.levels[k].last) return static_cast<int>(k);
    return -1;
  };
  EXPECT_EQ(levelOf(weak, 3.0f), levelOf(weak, 20.0f));
  const BandPlan strong = planBands(waves({{20.0f, 0.1f}, {3.0f, 0.1f * 20.0f / 3.0f}}), 0, 8);
  EXPECT_NE(levelOf(strong, 3.0f), levelOf(strong, 20.0f));
  EXPECT_EQ(strong.levels.size(), 2u);
}

// At most maxLevels levels; bands = 1 is the image itself; a request above what the image holds
// is cut to it.
TEST(BandPlan, LevelCountLimits) {
  const HeightTable t = mixture(128, 128, true);
  EXPECT_LE(planBands(t, 0, 2, 0.0).levels.size(), 2u);
  const BandPlan one = planBands(t, 1, 8);
  EXPECT_EQ(one.bands, 1);
  ASSERT_EQ(one.levels.size(), 1u);
  EXPECT_EQ(bandLevelTable(t, 1, 0, 0).texels(), t.texels());
  EXPECT_EQ(planBands(t, 99, 8, 0.0).bands, maxBandLevels(t));
}

}  // namespace
}  // namespace meso

namespace meso {
namespace {

// One stray texel does not flip the level that holds the image's waves to the Nyquist limit: its
// energy is white, so most of it lands in the finest bands (a level of its own, or merged into
// the finest), while the coarser level keeps a band-limited frequency. (As one level, the stray
// texel sets the image's frequency: the test checks that too, so that it can fail.)
TEST(BandPlan, AStrayTexelDoesNotFlipTheCoarseLevelToNyquist) {
  const HeightTable clean = waves({{6.0f, 0.2f}, {20.0f, 0.06f}});
  std::vector<float> texels = clean.texels();
  texels[37 * 128 + 91] += 2.0f;
  const HeightTable stray(128, 128, std::move(texels), HeightTableOptions{true});
  EXPECT_GT(stray.highestFrequency(), 2.0f * clean.highestFrequency());
  const BandPlan a = planBands(clean, 0, 8), b = planBands(stray, 0, 8);
  ASSERT_GE(a.levels.size(), 1u);
  ASSERT_GE(b.levels.size(), 1u);
  const HeightTable la = bandLevelTable(clean, a.bands, a.levels[0].first, a.levels[0].last);
  const HeightTable lb = bandLevelTable(stray, b.bands, b.levels[0].first, b.levels[0].last);
  // The stray texel's white spectrum reaches the coarse band too, up to its edge (6 -> 9 cycles
  // measured), but no further: far from the Nyquist limit the whole image jumps to.
  EXPECT_LE(lb.highestFrequency(), 1.6f * la.highestFrequency());
  EXPECT_LT(lb.highestFrequency(), 0.25f * stray.highestFrequency());
}

}  // namespace
}  // namespace meso
