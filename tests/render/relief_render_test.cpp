// Rendering relief: every algorithm gives finite images at the extremes, the BRDF agrees with
// redistribution in mean intensity on a flat patch, and auto is continuous across the thresholds.
#include "meso/render/film_layout.h"
#include "meso/render/integrator.h"

#include "support/plane_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace meso {
namespace {

namespace fs = std::filesystem;

Scene reliefScene(const std::string& algorithm, float amplitude) {
  Material m;
  m.kd = Vec3(0.8f);
  m.ks = Vec3(0.2f);
  m.relief = {testing::noiseLevel(amplitude, 1.0f)};
  Scene s = testing::planeScene(testing::writePlaneObj("relief", 50.0f, 0.0f, 100.0f), algorithm, m,
                                Vec3(0.2f, 0.7f, -0.6f), "relief");
  s.camera.position = {0.0f, -6.0f, 1.2f};
  s.camera.lookAt = {0.0f, 0.0f, 0.0f};
  s.camera.width = 64;
  s.camera.height = 48;
  s.camera.fovY = 50.0f;
  s.render.tessellationRate = 1;
  return s;
}

Image render(const Scene& scene) {
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(scene, times);
  RenderCounters counters;
  Image img = renderFrame(ctx, {scene.camera.spp, 3, false}, counters);
  EXPECT_EQ(counters.nonFinite.load(), 0) << "the renderer's own NaN/Inf check fired";
  return img;
}

double meanRed(const Image& img, int y0, int y1) {
  double sum = 0.0;
  for (int y = y0; y < y1; ++y)
    for (int x = 0; x < img.width; ++x) sum += img.at(x, y, FilmLayout::R);
  return sum / ((y1 - y0) * img.width);
}

TEST(ReliefRender, EveryAlgorithmIsFiniteAtTheExtremes) {
  for (const char* algorithm : {"auto", "bump", "redistribution", "brdf", "displacement"})
    for (float amplitude :
         {0.0f, 1e-9f, 0.002f, 0.5f}) {  // zero relief to relief taller than its wavelength
      Scene s = reliefScene(algorithm, amplitude);
      for (float height : {1e-4f, 1.2f, 1e4f}) {  // grazing to overhead, near and far
        s.camera.position = {0.0f, -6.0f, height};
        const Image img = render(s);
        EXPECT_TRUE(img.allFinite()) << algorithm << " " << amplitude << " " << height;
      }
    }
}

// Zero relief: every renderer is the smooth surface's shading, to float rounding (BRDF: to the
// table's trilinear interpolation of cos theta_L).
TEST(ReliefRender, ZeroReliefMakesAllRenderersAgree) {
  const Image bump = render(reliefScene("bump", 0.0f));
  for (const char* algorithm : {"redistribution", "brdf", "auto"}) {
    const Image other = render(reliefScene(algorithm, 0.0f));
    double worst = 0.0;
    for (size_t i = 0; i < bump.pixels.size(); i += bump.numChannels())
      worst = std::max(worst, static_cast<double>(std::abs(bump.pixels[i] - other.pixels[i])));
    EXPECT_LT(worst, 0.02) << algorithm;
  }
}

// The image is continuous across every threshold: in auto mode, the mean intensity of thin bands
// of rows on both sides of any row where a blend weight is strictly between 0 and 1 (or next to
// one) differs by less than 1%. Rows run from far to near across the plane, so T sweeps from
// below e1 (brdf) through e2 (redistribution) and e3 to beyond e4 (displaced micropolygons).
TEST(ReliefRender, AutoIsContinuousAcrossThresholds) {
  Scene s = reliefScene("auto", 0.002f);
  // scale 1: the shortest wavelength is 1/8 unit, so T crosses all four thresholds in the image.
  s.camera.width = 96;
  s.camera.height = 96;
  s.camera.fovY = 60.0f;
  s.camera.lookAt = {0.0f, 4.0f, 0.0f};
  s.camera.position = {0.0f, -1.0f, 2.0f};
  s.camera.spp = 4;
  const Image img = render(s);
  const int R = FilmLayout::AlgorithmR, G = FilmLayout::AlgorithmG, B = FilmLayout::AlgorithmB,
            depth = FilmLayout::DepthZ;
  int brdfRows = 0, redistRows = 0, dispRows = 0, firstFullRow = img.height;
  for (int y = 0; y < img.height; ++y) {
    const int x = img.width / 2;
    const float r = img.at(x, y, R), g = img.at(x, y, G), b = img.at(x, y, B);
    brdfRows += r > 0.99f && g > 0.99f && b < 0.01f;
    redistRows += b > 0.99f;
    dispRows += r > 0.99f && g < 0.01f;
    bool full = true;  // every pixel of the row sees the plane (no horizon)
    for (int i = 0; i < img.width; ++i) full = full && img.at(i, y, depth) > 0.0f;
    if (full) firstFullRow = std::min(firstFullRow, y);
  }
  ASSERT_GT(brdfRows, 3) << "the test scene must show the BRDF region";
  ASSERT_GT(redistRows, 3) << "the test scene must show the redistribution region";
  ASSERT_GT(dispRows, 3) << "the test scene must show the displaced region";
  const auto fractional = [&](int y) {
    for (int c : {R, G, B}) {
      const float w = img.at(img.width / 2, y, c);
      if (w > 0.001f && w < 0.999f) return true;
    }
    return false;
  };
  int checked = 0;
  for (int y = firstFullRow + 3; y + 3 < img.height; ++y) {
    if (!fractional(y) && !fractional(y - 1)) continue;
    const double above = meanRed(img, y - 3, y), below = meanRed(img, y, y + 3);
    EXPECT_LT(std::abs(above - below) / below, 0.01) << "rows " << y - 3 << ".." << y + 3;
    ++checked;
  }
  EXPECT_GT(checked, 8);  // both blend regions (e1..e2 and e3..e4) are several rows tall
}

}  // namespace
}  // namespace meso
