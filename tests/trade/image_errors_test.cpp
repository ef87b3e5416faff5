// Image errors against a reference: zero for identical frames, the known figures for a constant
// offset, averaged over frames; the local contrast per depth band, noise-corrected with the second
// seed's frames; different sizes are refused.
#include "meso/trade/image_errors.h"

#include "meso/core/error.h"
#include "meso/core/rng.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using meso::trade::RgbImage;

RgbImage constant(int w, int h, float v) {
  return {w, h, std::vector<float>(static_cast<size_t>(w) * h * 3, v)};
}

TEST(ImageErrors, IdenticalFramesHaveNoError) {
  const std::vector<RgbImage> a = {constant(4, 3, 0.25f)};
  const meso::trade::ImageErrors e = meso::trade::compareFrames(a, a);
  EXPECT_EQ(e.meanAbsError, 0.0);
  EXPECT_EQ(e.rmse, 0.0);
  EXPECT_EQ(e.intensityErrorPct, 0.0);
}

TEST(ImageErrors, ConstantOffsetAveragedOverFrames) {
  const std::vector<RgbImage> img = {constant(4, 3, 0.75f), constant(4, 3, 0.5f)};
  const std::vector<RgbImage> ref = {constant(4, 3, 0.5f), constant(4, 3, 0.5f)};
  const meso::trade::ImageErrors e = meso::trade::compareFrames(img, ref);
  EXPECT_DOUBLE_EQ(e.meanAbsError, 0.125);      // (0.25 + 0) / 2
  EXPECT_DOUBLE_EQ(e.rmse, 0.125);              // per frame sqrt(0.0625) = 0.25, then 0
  EXPECT_DOUBLE_EQ(e.intensityErrorPct, 25.0);  // (50% + 0%) / 2
}

// Depth bands split the reference's hits into equal counts, near to far; the worst band's signed
// error is the one of largest magnitude, averaged over frames; pixels the reference misses (depth
// 0) do not count.
TEST(ImageErrors, WorstDepthBandIsSignedAndIgnoresMisses) {
  RgbImage ref = constant(10, 1, 0.5f), img = constant(10, 1, 0.5f);
  std::vector<float> depth(10);
  for (int i = 0; i < 10; ++i) depth[i] = static_cast<float>(10 - i);  // far to near
  depth[9] = 0.0f;  // the reference misses pixel 9: its error must not count
  for (int c = 0; c < 3; ++c) {
    img.rgb[3 * 9 + c] = 100.0f;
    img.rgb[3 * 0 + c] = 0.4f;  // the farthest hit
  }
  const meso::trade::ImageErrors e = meso::trade::compareFrames({img}, {ref}, {depth});
  // 9 hits in 5 bands of 1, 2, 2, 2, 2 (k from 9 b / 5): the farthest holds depths 9 and 10, one
  // of them 0.4 against 0.5: -10%.
  EXPECT_NEAR(e.worstBandPct, -10.0, 1e-5);
  // Without depth, no band figure; the plain errors see the miss.
  EXPECT_EQ(meso::trade::compareFrames({img}, {ref}).worstBandPct, 0.0);
  EXPECT_GT(meso::trade::compareFrames({img}, {ref}).intensityErrorPct, 100.0);
}

// 160 x 64 pixels, depth growing to the right: five depth bands of 32 columns, 32 blocks each.
constexpr int kW = 160, kH = 64;

// A checkerboard of `amplitude` about 0.5 (grey), plus uniform noise in [-noise, noise] of stream
// `seed`, in the columns [x0, x1) only (0.5 elsewhere).
RgbImage checker(double amplitude, int x0 = 0, int x1 = kW, double noise = 0.0, uint64_t seed = 1) {
  RgbImage im = constant(kW, kH, 0.5f);
  meso::Rng rng(seed);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const double n = noise * (2.0 * rng.uniform() - 1.0);
      const double v = 0.5 + n + (x >= x0 && x < x1 ? ((x + y) % 2 ? amplitude : -amplitude) : 0.0);
      for (int c = 0; c < 3; ++c) im.rgb[3 * (y * kW + x) + c] = static_cast<float>(v);
    }
  return im;
}

std::vector<float> depthToTheRight() {
  std::vector<float> depth(kW * kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) depth[y * kW + x] = 1.0f + static_cast<float>(x);
  return depth;
}

// The reference's texture erased in the farthest band only: the mean is the same everywhere, the
// worst contrast ratio is that band's 0. Identical frames give 1; a flat reference shows no
// relief (NaN) and neither does a comparison without depth.
TEST(ImageErrors, WorstContrastRatioPerDepthBand) {
  const RgbImage ref = checker(0.05);
  const std::vector<std::vector<float>> depth = {depthToTheRight()};
  const meso::trade::ImageErrors erased =
      meso::trade::compareFrames({checker(0.05, 0, 128)}, {ref}, depth);
  EXPECT_NEAR(erased.worstBandPct, 0.0, 1e-4);
  EXPECT_EQ(erased.worstContrastRatio, 0.0);
  EXPECT_NEAR(meso::trade::compareFrames({ref}, {ref}, depth).worstContrastRatio, 1.0, 1e-12);
  EXPECT_NEAR(meso::trade::compareFrames({checker(0.04)}, {ref}, depth).worstContrastRatio, 0.8,
              1e-5);
  EXPECT_TRUE(std::isnan(
      meso::trade::compareFrames({ref}, {constant(kW, kH, 0.5f)}, depth).worstContrastRatio));
  EXPECT_TRUE(std::isnan(meso::trade::compareFrames({ref}, {ref}).worstContrastRatio));
}

// Noise of 5.8% of the mean per pixel on the reference's texture (10% contrast) reads as 15% more
// contrast; the second seed's frames take it out again.
TEST(ImageErrors, SecondSeedFramesTakeSamplingNoiseOut) {
  const RgbImage ref = checker(0.05);
  const std::vector<std::vector<float>> depth = {depthToTheRight()};
  const RgbImage noisy = checker(0.05, 0, kW, 0.05, 1), again = checker(0.05, 0, kW, 0.05, 2);
  const double raw = meso::trade::compareFrames({noisy}, {ref}, depth).worstContrastRatio;
  EXPECT_GT(raw, 1.1);
  const double corrected =
      meso::trade::compareFrames({noisy}, {ref}, depth, {again}, {ref}).worstContrastRatio;
  EXPECT_NEAR(corrected, 1.0, 0.04);
  EXPECT_THROW(meso::trade::compareFrames({noisy}, {ref}, depth, {constant(4, 3, 0.5f)}, {ref}),
               meso::Error);
}

TEST(ImageErrors, RefusesDifferentSizes) {
  EXPECT_THROW(meso::trade::compareFrames({constant(4, 3, 0.0f)}, {constant(3, 4, 0.0f)}),
               meso::Error);
}

}  // namespace
