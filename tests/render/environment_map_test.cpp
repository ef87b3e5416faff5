// The environment's importance sampling: the map's coordinates, its density against its own
// table (chi-square), the density integrating to 1 over the sphere, and the per-sample lights'
// irradiance estimate.
#include "meso/core/rng.h"
#include "meso/render/environment_map.h"

#include "support/chi_square.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

namespace meso {
namespace {

// A map with smooth variation, a dark band and one bright texel (a sun), 32 x 16.
Image testMap() {
  Image img(32, 16, {"R", "G", "B"});
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const float sky = 0.4f + 0.8f * static_cast<float>(y) / 16.0f +
                        0.3f * std::sin(0.4f * static_cast<float>(x));
      const float dark = y == 10 ? 0.0f : 1.0f;
      for (int k = 0; k < 3; ++k) img.at(x, y, k) = dark * sky * (1.0f + 0.2f * k);
    }
  for (int k = 0; k < 3; ++k) img.at(20, 4, k) = 400.0f;
  return img;
}

EnvironmentDecl turned(float rotation, Vec3 up) {
  EnvironmentDecl d;
  d.rotation = rotation;
  d.up = glm::normalize(up);
  return d;
}

TEST(EnvironmentMap, MapCoordinatesFollowTheDocumentedConvention) {
  const Image one(1, 1, {"R", "G", "B"});
  const EnvironmentMap plain(one, EnvironmentDecl{});
  const auto near = [](const Vec3& a, const Vec3& b) { return glm::length(a - b) < 1e-5f; };
  EXPECT_TRUE(near(plain.direction({0.5f, 0.5f}), Vec3(0.0f, 0.0f, -1.0f)));
  EXPECT_TRUE(near(plain.direction({0.75f, 0.5f}), Vec3(1.0f, 0.0f, 0.0f)));
  EXPECT_TRUE(near(plain.direction({0.25f, 0.5f}), Vec3(-1.0f, 0.0f, 0.0f)));
  EXPECT_TRUE(near(plain.direction({0.3f, 0.0f}), Vec3(0.0f, 1.0f, 0.0f)));
  // rotation turns counter-clockwise seen from above: the centre column's -z goes to -x.
  const EnvironmentMap turnedMap(one, turned(90.0f, Vec3(0.0f, 1.0f, 0.0f)));
  EXPECT_TRUE(near(turnedMap.direction({0.5f, 0.5f}), Vec3(-1.0f, 0.0f, 0.0f)));
  // up = +z: the top row is +z.
  const EnvironmentMap zUp(one, turned(0.0f, Vec3(0.0f, 0.0f, 1.0f)));
  EXPECT_TRUE(near(zUp.direction({0.1f, 0.0f}), Vec3(0.0f, 0.0f, 1.0f)));
  // Round trips, for every frame.
  Rng rng(3);
  for (const EnvironmentMap* m : {&plain, &turnedMap, &zUp})
    for (int i = 0; i < 1000; ++i) {
      const Vec2 uv(rng.uniform(), 0.01f + 0.98f * rng.uniform());
      const Vec2 back = m->mapCoordinates(m->direction(uv));
      EXPECT_NEAR(back.x, uv.x, 2e-5f);
      EXPECT_NEAR(back.y, uv.y, 2e-5f);
    }
}

// The density per solid angle integrates to 1 over the sphere (midpoint rule on a grid much finer
// than the texels, in a frame other than the map's), and sample() reports pdf() and radiance() of
// the direction it returns.
TEST(EnvironmentMap, DensityIntegratesToOneAndSamplesReportIt) {
  const EnvironmentMap env(testMap(), turned(37.0f, Vec3(0.3f, 0.2f, 1.0f)));
  const int nTheta = 1600, nPhi = 3200;
  double integral = 0.0;
  for (int i = 0; i < nTheta; ++i) {
    const double theta = kPi * (i + 0.5) / nTheta;
    for (int j = 0; j < nPhi; ++j) {
      const double phi = 2.0 * kPi * (j + 0.5) / nPhi;
      const Vec3 w(static_cast<float>(std::sin(theta) * std::cos(phi)),
                   static_cast<float>(std::sin(theta) * std::sin(phi)),
                   static_cast<float>(std::cos(theta)));
      integral += env.pdf(w) * std::sin(theta) * (kPi / nTheta) * (2.0 * kPi / nPhi);
    }
  }
  EXPECT_NEAR(integral, 1.0, 2e-3);
  Rng rng(5);
  for (int i = 0; i < 2000; ++i) {
    const EnvironmentMap::Sample s = env.sample({rng.uniform(), rng.uniform()});
    ASSERT_GT(s.pdf, 0.0f);
    EXPECT_NEAR(glm::length(s.w), 1.0f, 1e-5f);
    EXPECT_NEAR(env.pdf(s.w) / s.pdf, 1.0f, 5e-3f);  // sin(theta) of a round trip near a pole
    EXPECT_NEAR(env.radiance(s.w).g / s.radiance.g, 1.0f, 1e-5f);
  }
}

// Sampled directions binned by texel against each texel's probability, luminance x solid angle
// over the whole map's (computed here from the image, not from the map's tables).
TEST(EnvironmentMap, SampledTexelsFollowLuminanceTimesSolidAngle) {
  const Image img = testMap();
  const EnvironmentMap env(img, turned(-20.0f, Vec3(1.0f, 1.0f, 0.0f)));
  const int w = img.width, h = img.height;
  std::vector<double> expected(static_cast<size_t>(w * h), 0.0);
  double total = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double lum =
          0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2);
      const double solid = std::cos(kPi * y / h) - std::cos(kPi * (y + 1) / h);
      expected[static_cast<size_t>(y * w + x)] = lum * solid;
      total += lum * solid;
    }
  const int n = 400000;
  std::vector<double> observed(expected.size(), 0.0);
  Rng rng(7);
  for (int i = 0; i < n; ++i) {
    const Vec2 uv = env.mapCoordinates(env.sample({rng.uniform(), rng.uniform()}).w);
    const int x = std::clamp(static_cast<int>(uv.x * w), 0, w - 1);
    const int y = std::clamp(static_cast<int>(uv.y * h), 0, h - 1);
    observed[static_cast<size_t>(y * w + x)] += 1.0;
  }
  for (double& e : expected) e *= n / total;
  // The map's rows take sin(theta) at their centres: their masses differ from the exact solid
  // angles by (1 - sinc(pi / 2h)) = 0.16% at most, far below this test's resolution.
  const testing::ChiSquareResult r = testing::chiSquareTest(observed, expected);
  if (r.pValue < 0.01) testing::dumpTable(observed, expected);
  EXPECT_GE(r.pValue, 0.01) << "chi2 " << r.chi2 << " dof " << r.dof;
  EXPECT_EQ(observed[static_cast<size_t>(10 * w + 3)], 0.0) << "a black texel is never sampled";
}

// The lights of one camera sample estimate the irradiance of a uniform sky of radiance L on a
// plane: pi L; averaged over many samples' scrambles, to 0.2%; each sample's own estimate (64
// lights) within 10%.
TEST(EnvironmentMap, SampleLightsEstimateTheIrradianceOfAUniformSky) {
  Image one(1, 1, {"R", "G", "B"});
  for (int k = 0; k < 3; ++k) one.at(0, 0, k) = 1.0f;
  EnvironmentDecl d;
  d.colour = Vec3(0.5f, 1.0f, 2.0f);
  const EnvironmentMap env(one, d);
  const Vec3 N = glm::normalize(Vec3(0.2f, 0.9f, -0.3f));
  std::array<Light, 64> lights;
  double sum = 0.0, worst = 0.0;
  const int keys = 4000;
  for (int k = 0; k < keys; ++k) {
    environmentLights(env, environmentSampleKey(Vec2(0.37f * k, 0.11f * k), 9), lights);
    double e = 0.0;
    for (const Light& l : lights) e += l.colour.g * std::max(0.0f, glm::dot(-l.direction, N));
    sum += e;
    worst = std::max(worst, std::abs(e / kPi - 1.0));
  }
  EXPECT_NEAR(sum / keys / kPi, 1.0, 2e-3);
  EXPECT_LT(worst, 0.1);
}

}  // namespace
}  // namespace meso
