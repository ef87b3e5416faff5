#include "meso/appearance/table_plots.h"

#include <gtest/gtest.h>

namespace meso {
namespace {

TEST(TablePlots, PanelsHaveTheExpectedSizeAndFiniteColours) {
  VisibleNormalHistogram h(HistogramResolution{6, 8, 10});
  for (int k = 0; k < 6; ++k) h.add(k, glm::normalize(Vec3(0.1f * k, 0.0f, 1.0f)));
  h.normalize();
  const Image a = plotHistogram(h, 4);
  EXPECT_EQ(a.width, 4 * (8 * 4 + 3) + 3);
  EXPECT_EQ(a.height, 2 * (10 * 4 + 3) + 3);
  EXPECT_TRUE(a.allFinite());
  const BrdfTable b = BrdfTable::fromDistribution(h, {5, 4}, 10.0f);
  const Image c = plotBrdf(b, 2);
  EXPECT_EQ(c.width, 6 * (5 * 2 + 3) + 3);
  EXPECT_TRUE(c.allFinite());
  // The brightest diffuse cell (L at the zenith) is the top of the ramp (yellow: R > 0.9).
  EXPECT_GT(c.at(3, 3, 0), 0.9f);
}

}  // namespace
}  // namespace meso
