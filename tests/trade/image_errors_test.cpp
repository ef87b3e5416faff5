// Image errors against a reference: zero for identical frames, the known figures for a constant
// offset, averaged over frames; different sizes are refused.
#include "meso/trade/image_errors.h"

#include "meso/core/error.h"

#include <gtest/gtest.h>

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

TEST(ImageErrors, RefusesDifferentSizes) {
  EXPECT_THROW(meso::trade::compareFrames({constant(4, 3, 0.0f)}, {constant(3, 4, 0.0f)}),
               meso::Error);
}

}  // namespace
