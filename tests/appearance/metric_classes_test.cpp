// The metric classes of docs/metric.md (metric_classes.h): each bin of shapes gets its samples'
// mean shape, and garbage metrics fit the class cap and the shape clamps.
#include "meso/appearance/metric_classes.h"

#include "meso/core/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace meso {
namespace {

// A class takes the mean shape of the samples in its bin, not the bin's grid point: one shape (a
// stretched or sheared plane) gives exactly that shape; two shapes in one bin give their geometric
// mean in a and mean in b; exact identities stay exactly the identity, and a mild stretch shares
// the identity's bin but not its shape.
TEST(Metric, ClassesTakeTheMeanShapeOfTheirBin) {
  const auto shaped = [](float l, float a, float b) { return MetricClass{l, MetricShape{a, b}}; };
  const std::vector<MetricClass> one = {shaped(2.0f, 0.316f, 0.0f), shaped(2.0f, 0.316f, 0.0f)};
  const std::vector<MetricClass> k1 = metricClassesFor(one, 0.25f);
  ASSERT_EQ(k1.size(), 1u);
  EXPECT_EQ(k1[0].shape.a, 0.316f) << "the 0.25-octave grid point is 0.297";
  EXPECT_EQ(k1[0].shape.b, 0.0f);
  EXPECT_EQ(k1[0].lengthPerU, 2.0f);
  const std::vector<MetricClass> two = {shaped(1.0f, 0.33f, 0.38f), shaped(1.0f, 0.36f, 0.42f)};
  const std::vector<MetricClass> k2 = metricClassesFor(two, 0.25f);
  ASSERT_EQ(k2.size(), 1u);
  EXPECT_NEAR(k2[0].shape.a, std::sqrt(0.33f * 0.36f), 1e-6f);
  EXPECT_NEAR(k2[0].shape.b, 0.40f, 1e-6f);
  const std::vector<MetricClass> unit = {shaped(1.0f, 1.0f, 0.0f), shaped(1.5f, 1.0f, 0.0f)};
  for (const MetricClass& c : metricClassesFor(unit, 0.25f)) EXPECT_TRUE(c.shape.identity());
  const std::vector<MetricClass> mild = {shaped(1.0f, 1.05f, 0.0f)};
  EXPECT_EQ(metricClassesFor(mild, 0.25f).at(0).shape.a, 1.05f);
}

// Garbage metrics (a mesh so far from the origin that its float positions collapse once asked
// for 111 classes): at most kMaxMetricClasses, at a coarser step, every shape within the clamps.
// A sphere's range of metrics keeps the requested step.
TEST(Metric, GarbageMetricsFitTheClassCapAndTheShapeClamps) {
  Rng rng(3);
  std::vector<MetricClass> garbage;
  for (int k = 0; k < 2000; ++k)
    garbage.push_back(
        {std::exp2(40.0f * rng.uniform() - 20.0f),
         MetricShape{std::exp2(24.0f * rng.uniform() - 12.0f), 2000.0f * rng.uniform() - 1000.0f}});
  float step = 0.0f;
  const std::vector<MetricClass> classes = metricClassesFor(garbage, 0.25f, &step);
  EXPECT_LE(classes.size(), kMaxMetricClasses);
  EXPECT_GE(classes.size(), 2u);
  EXPECT_GT(step, 0.25f) << "the cap must have coarsened the step";
  for (const MetricClass& c : classes) {
    EXPECT_GE(c.shape.a, 1.0f / kMaxMetricStretch);
    EXPECT_LE(c.shape.a, kMaxMetricStretch);
    EXPECT_LE(std::abs(c.shape.b), kMaxMetricShear);
    EXPECT_TRUE(std::isfinite(c.lengthPerU) && c.lengthPerU > 0.0f);
  }
  // A UV sphere's metrics (u once around, v pole to pole): on the ring of radius r, |P_u| = 2 pi r
  // and |P_v| = pi, so l = pi sqrt(2 r) and a = sqrt(2 r), r from 0.05 to 1.
  std::vector<MetricClass> sphere;
  for (int k = 0; k <= 100; ++k) {
    const float r = 0.05f + 0.0095f * static_cast<float>(k);
    sphere.push_back({kPi * std::sqrt(2.0f * r), MetricShape{std::sqrt(2.0f * r), 0.0f}});
  }
  const std::vector<MetricClass> kept = metricClassesFor(sphere, 0.25f, &step);
  EXPECT_EQ(step, 0.25f);
  EXPECT_GT(kept.size(), 1u);
  EXPECT_LE(kept.size(), kMaxMetricClasses);
}

}  // namespace
}  // namespace meso
