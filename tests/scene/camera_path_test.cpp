#include "meso/core/error.h"
#include "meso/scene/camera_path.h"

#include <gtest/gtest.h>

namespace meso {
namespace {

std::vector<CameraKeyframe> keys() {
  return {{0.0f, {0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 40},
          {1.0f, {3, 1, 6}, {0, 0, 0}, {0, 1, 0}, 30},
          {3.5f, {1, 0.5f, 1}, {0.2f, 0, 0}, {0, 1, 0.1f}, 20},
          {4.0f, {0, 0.1f, 0.2f}, {0, 0, 0}, {0, 1, 0}, 10}};
}

TEST(CameraPath, PassesThroughItsKeyframes) {
  const CameraPath path(keys());
  for (const CameraKeyframe& k : keys()) {
    const CameraKeyframe p = path.at(k.time);
    EXPECT_NEAR(glm::length(p.position - k.position), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::length(p.lookAt - k.lookAt), 0.0f, 1e-5f);
    EXPECT_NEAR(p.fovY, k.fovY, 1e-4f);
  }
}

// The first derivative is continuous at interior keyframes: one-sided difference quotients from
// the left and from the right agree to O(h), unlike linear interpolation's kinks.
TEST(CameraPath, FirstDerivativeIsContinuous) {
  const CameraPath path(keys());
  for (float t : {1.0f, 3.5f}) {
    for (float h : {1e-2f, 1e-3f}) {
      const Vec3 left = (path.at(t).position - path.at(t - h).position) / h;
      const Vec3 right = (path.at(t + h).position - path.at(t).position) / h;
      EXPECT_LT(glm::length(left - right), 40.0f * h) << t << " " << h;
    }
  }
  // A linear path through the same keys has a kink of order 1: the test above would catch it.
  const Vec3 slopeIn = (keys()[1].position - keys()[0].position) / 1.0f;
  const Vec3 slopeOut = (keys()[2].position - keys()[1].position) / 2.5f;
  EXPECT_GT(glm::length(slopeIn - slopeOut), 1.0f);
}

TEST(CameraPath, FramesSpanThePathAndClamp) {
  const CameraPath path(keys());
  CameraSettings base;
  base.width = 64;
  const CameraSettings first = path.frame(0, 48, base), last = path.frame(47, 48, base);
  EXPECT_EQ(first.position, keys().front().position);
  EXPECT_NEAR(glm::length(last.position - keys().back().position), 0.0f, 1e-5f);
  EXPECT_EQ(last.width, 64);
  EXPECT_EQ(path.at(-5.0f).position, keys().front().position);
  EXPECT_EQ(path.at(50.0f).position, keys().back().position);
}

TEST(CameraPath, RejectsBadKeyframes) {
  EXPECT_THROW(CameraPath({}), Error);
  auto k = keys();
  k[2].time = 1.0f;
  EXPECT_THROW(CameraPath{k}, Error);
}

}  // namespace
}  // namespace meso
