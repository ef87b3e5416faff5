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
