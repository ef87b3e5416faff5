// Schilling's antialiased bump mapping in the bump renderer: slopes averaged over the ray
// footprint and the highlight widened by the removed roughness approach the supersampled image
// with one sample per pixel; the roughened highlight reduces to Blinn-Phong on a smooth surface.
#include "meso/render/film_layout.h"
#include "meso/render/integrator.h"
#include "meso/render/shading.h"
#include "meso/render/surface_shader.h"

#include "meso/core/rng.h"

#include "support/plane_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace meso {
namespace {

namespace fs = std::filesystem;

Scene farReliefScene() {
  Material m;
  m.kd = Vec3(0.3f);
  m.ks = Vec3(0.7f);
  m.phong = 40.0f;
  m.relief = {
      testing::noiseLevel(0.02f, 2.0f)};  // slopes about 0.5: strong, many waves per pixel far away
  // Light towards the eye: a broad highlight.
  Scene s = testing::planeScene(testing::writePlaneObj("bumpf", 20.0f, 0.0f, 40.0f), "bump", m,
                                Vec3(0.0f, -0.6f, -0.5f), "bumpf");
  s.camera.position = {0.0f, -12.0f, 5.0f};
  s.camera.lookAt = {0.0f, 2.0f, 0.0f};
  s.camera.width = 40;
  s.camera.height = 30;
  s.camera.fovY = 40.0f;
  return s;
}

Image render(const Scene& s, int spp, bool filter) {
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(s, times);
  RenderCounters counters;
  RenderOptions o{spp, 9, false};
  o.filterBump = filter;
  Image img = renderFrame(ctx, o, counters);
  EXPECT_EQ(counters.nonFinite.load(), 0) << "the renderer's own NaN/Inf check fired";
  return img;
}

double rmse(const Image& a, const Image& b) {
  double sum = 0.0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = FilmLayout::R; c <= FilmLayout::B; ++c)
        sum += std::pow(a.at(x, y, c) - b.at(x, y, c), 2.0);
  return std::sqrt(sum / (3.0 * a.width * a.height));
}

TEST(BumpFilter, OneFilteredSampleIsCloserToTheSupersampledImage) {
  const Scene s = farReliefScene();
  const Image reference = render(s, 256, false);
  const Image filtered = render(s, 1, true), pointSampled = render(s, 1, false);
  ASSERT_TRUE(filtered.allFinite());
  const double ef = rmse(filtered, reference), ep = rmse(pointSampled, reference);
  std::printf("  rmse against 256 spp: filtered %.4f, point-sampled %.4f\n", ef, ep);
  const auto mean = [](const Image& im) {
    double sum = 0.0;
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x) sum += im.at(x, y, FilmLayout::R);
    return sum / (im.width * im.height);
  };
  std::printf("  mean intensity: reference %.4f, filtered %.4f\n", mean(reference), mean(filtered));
  EXPECT_LT(ef, 0.3 * ep);  // measured 0.020 against 0.141
  EXPECT_NEAR(mean(filtered), mean(reference),
              0.02 * mean(reference));  // the lobe keeps its energy
}

TEST(BumpFilter, RoughenedHighlightIsBlinnPhongWithoutRoughness) {
  Material m;
  m.kd = Vec3(0.2f);
  m.ks = Vec3(0.8f);
  m.phong = 25.0f;
  Light l;
  Rng rng(3);
  for (int k = 0; k < 100; ++k) {
    l.direction = -glm::normalize(Vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, 1.0f));
    const Vec3 V = glm::normalize(Vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, 1.0f));
    const Vec3 N(0, 0, 1), e1(1, 0, 0), e2(0, 1, 0);
    const Vec3 plain = shadeLocal(m, std::span<const Light>(&l, 1), Vec3(0.0f), N, V);
    const Vec3 rough0 =
        shadeRoughened(m, std::span<const Light>(&l, 1), Vec3(0.0f), N, V, e1, e2, {});
    EXPECT_NEAR(plain.x, rough0.x, 1e-4f * (1.0f + plain.x));
    // Roughness widens the highlight: the peak falls and the tails rise, never above the smooth
    // peak.
    const Vec3 rough = shadeRoughened(m, std::span<const Light>(&l, 1), Vec3(0.0f), N, V, e1, e2,
                                      {0.01f, 0.0f, 0.01f});
    EXPECT_TRUE(isFinite(rough));
    EXPECT_LE(rough.x, m.ka.x + m.kd.x + m.ks.x + 1e-5f);
  }
}

// The footprint of a pixel on a plane seen head-on is one pixel's world size divided by the
// length of P_u: du/dx = distance / (pixels per radian * |P_u|).
TEST(BumpFilter, FootprintOfAPlaneSeenHeadOn) {
  CameraSettings cs;
  cs.position = {0.0f, 0.0f, 10.0f};
  cs.lookAt = {0.0f, 0.0f, 0.0f};
  cs.width = 100;
  cs.height = 100;
  cs.fovY = 40.0f;
  const Camera camera(cs);
  SurfacePoint sp;
  sp.P = Vec3(0.0f);
  sp.Pu = Vec3(2.0f, 0.0f, 0.0f);
  sp.Pv = Vec3(0.0f, 2.0f, 0.0f);
  sp.N = Vec3(0.0f, 0.0f, 1.0f);
  const Footprint fp =
      footprintAt(sp, camera.generateRay(51.0f, 50.0f), camera.generateRay(50.0f, 51.0f), 1.0f);
  ASSERT_TRUE(fp.valid);
  const float expected = 10.0f / (camera.pixelsPerRadian() * 2.0f);
  EXPECT_NEAR(std::abs(fp.dUVdx.x), expected, 0.01f * expected);
  EXPECT_NEAR(fp.dUVdx.y, 0.0f, 0.01f * expected);
  EXPECT_NEAR(std::abs(fp.dUVdy.y), expected, 0.01f * expected);
  // A ray parallel to the plane gives no footprint rather than an infinite one.
  Ray parallel{Vec3(0, 0, 1), Vec3(1, 0, 0)};
  EXPECT_FALSE(footprintAt(sp, parallel, parallel, 1.0f).valid);
}

}  // namespace
}  // namespace meso
