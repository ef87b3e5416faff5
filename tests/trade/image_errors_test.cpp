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

TEST(ImageErrors, RefusesDifferentSizes) {
  EXPECT_THROW(meso::trade::compareFrames({constant(4, 3, 0.0f)}, {constant(3, 4, 0.0f)}),
               meso::Error);
}

}  // namespace
