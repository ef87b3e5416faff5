#include "meso/geometry/screen_metric.h"

#include "geometry/test_meshes.h"
#include "meso/core/rng.h"
#include "meso/scene/camera.h"

#include <gtest/gtest.h>

#include <cmath>

namespace meso {
namespace {

TEST(ScreenMetric, ProjectsLikeTheCamera) {
  CameraSettings settings;
  settings.position = Vec3(1.0f, 2.0f, 3.0f);
  settings.lookAt = Vec3(-1.0f, 0.5f, -2.0f);
  settings.fovY = 50.0f;
  const Camera camera(settings);
  const ScreenMetric screen = ScreenMetric::lookAt(settings.position, settings.lookAt, settings.up,
                                                   settings.fovY, settings.width, settings.height);
  Rng rng(5);
  for (int i = 0; i < 100; ++i) {
    const Vec2 pixel(800.0f * rng.uniform() - 80.0f, 400.0f * rng.uniform() - 20.0f);
    const Ray ray = camera.generateRay(pixel.x, pixel.y);
    const Vec2 found = screen.toPixels(ray.origin + (0.5f + 9.0f * rng.uniform()) * ray.direction);
    EXPECT_LT(glm::length(found - pixel), 1e-2f) << pixel.x << "," << pixel.y;
  }
}

TEST(ScreenMetric, ProjectedLengthClipsBehindTheEye) {
  const ScreenMetric screen =
      ScreenMetric::lookAt(Vec3(0.0f), Vec3(0, 0, -1), Vec3(0, 1, 0), 90.0f, 200, 100);
  // A unit segment across the view at depth 2: 100 / (2 tan 45 * 2) = 25 pixels per unit.
  EXPECT_NEAR(screen.projectedLength(Vec3(-0.5f, 0, -2), Vec3(0.5f, 0, -2)), 25.0f, 1e-4f);
  EXPECT_NEAR(screen.pixelsPerUnit(2.0f), 25.0f, 1e-4f);
  EXPECT_EQ(screen.projectedLength(Vec3(-1, 0, 1), Vec3(1, 0, 2)), 0.0f);  // wholly behind
  const float crossing = screen.projectedLength(Vec3(0.2f, 0, 1), Vec3(0.2f, 0, -1));
  EXPECT_TRUE(std::isfinite(crossing));
  EXPECT_GT(crossing, 0.0f);
}

TEST(ScreenMetric, FootprintLengthIsWorldLengthOverThePixelFootprint) {
  const ScreenMetric screen =
      ScreenMetric::lookAt(Vec3(0.0f), Vec3(0, 0, -1), Vec3(0, 1, 0), 90.0f, 200, 100);
  // Along the view axis from depth 2 to 3: nothing on screen, but k ln(3 / 2) footprints
  // (k = 50 pixels per unit at depth 1; Simpson's rule is within 3e-4 of the logarithm).
  EXPECT_LT(screen.projectedLength(Vec3(0, 0, -2), Vec3(0, 0, -3)), 1e-3f);
  EXPECT_NEAR(screen.footprintLength(Vec3(0, 0, -2), Vec3(0, 0, -3)), 50.0f * std::log(1.5f),
              50.0f * 3e-4f);
  // Across the axis at depth 2: about the projected 25 pixels (a little more off axis).
  const float across = screen.footprintLength(Vec3(-0.5f, 0, -2), Vec3(0.5f, 0, -2));
  EXPECT_GE(across, 25.0f);
  EXPECT_LT(across, 25.5f);
  EXPECT_NEAR(screen.pixelDensity(Vec3(0, 0, -2)), 25.0f, 1e-4f);
  EXPECT_NEAR(screen.pixelDensity(Vec3(2, 0, -2)), 25.0f * std::sqrt(2.0f), 1e-3f);
  EXPECT_EQ(screen.footprintLength(Vec3(-1, 0, 1), Vec3(1, 0, 2)), 0.0f);  // wholly behind
  // Never shorter than the projection, whatever the segment.
  Rng rng(17);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 a(4 * rng.uniform() - 2, 4 * rng.uniform() - 2, -0.1f - 5 * rng.uniform());
    const Vec3 b = a + 0.3f * test::randomDirection(rng);
    EXPECT_GE(screen.footprintLength(a, b), screen.projectedLength(a, b) * (1.0f - 1e-5f));
  }
}

TEST(ScreenMetric, BoxTestCullsOnlyBoxesOutsideTheFrustum) {
  const ScreenMetric screen =
      ScreenMetric::lookAt(Vec3(0.0f), Vec3(0, 0, -1), Vec3(0, 1, 0), 90.0f, 200, 100);
  EXPECT_TRUE(screen.boxInView(Vec3(-0.1f, -0.1f, -3.0f), Vec3(0.1f, 0.1f, -2.0f), 0.0f));
  EXPECT_FALSE(screen.boxInView(Vec3(-1.0f, -1.0f, 1.0f), Vec3(1.0f, 1.0f, 2.0f), 0.0f));
  // Half width at depth 1 is 2 (aspect 2), half height 1.
  EXPECT_FALSE(screen.boxInView(Vec3(2.5f, -0.1f, -1.1f), Vec3(3.0f, 0.1f, -1.0f), 0.0f));
  EXPECT_TRUE(screen.boxInView(Vec3(2.5f, -0.1f, -1.1f), Vec3(3.0f, 0.1f, -1.0f), 0.6f));
  EXPECT_FALSE(screen.boxInView(Vec3(-0.1f, 1.2f, -1.1f), Vec3(0.1f, 1.5f, -1.0f), 0.0f));
  // A box around the eye is always in view.
  EXPECT_TRUE(screen.boxInView(Vec3(-1.0f), Vec3(1.0f), 0.0f));
}

// Growing by a ball: a point 1 / sqrt(5) = 0.447 beside the right plane x = 2 depth is near the
// view within 0.5 and not within 0.4, which the box grown as a cube by 0.4 still reaches.
TEST(ScreenMetric, BallGrownBoxTestIsTighterBesideSlantedPlanes) {
  const ScreenMetric screen =
      ScreenMetric::lookAt(Vec3(0.0f), Vec3(0, 0, -1), Vec3(0, 1, 0), 90.0f, 200, 100);
  const Vec3 p(3.0f, 0.0f, -1.0f);
  EXPECT_FALSE(screen.boxNearView(p, p, 0.0f));
  EXPECT_FALSE(screen.boxNearView(p, p, 0.4f));
  EXPECT_TRUE(screen.boxNearView(p, p, 0.5f));
  EXPECT_TRUE(screen.boxInView(p, p, 0.4f));
  EXPECT_TRUE(screen.boxNearView(Vec3(-0.1f, -0.1f, -3.0f), Vec3(0.1f, 0.1f, -2.0f), 0.0f));
  EXPECT_FALSE(screen.boxNearView(Vec3(-1.0f, -1.0f, 1.0f), Vec3(1.0f, 1.0f, 2.0f), 0.5f));
}

}  // namespace
}  // namespace meso
