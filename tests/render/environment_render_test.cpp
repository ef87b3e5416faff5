// Environment lighting in renders (docs/environment.md): a diffuse plane under a uniform sky is
// kd pi L, converging with the light samples; a sky whose light is one bright texel lights relief
// as a directional light of the same irradiance does; images are the same for any thread count.
#include "meso/core/image_io.h"
#include "meso/render/film_layout.h"
#include "meso/render/integrator.h"

#include "support/plane_scene.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <filesystem>

namespace meso {
namespace {

namespace fs = std::filesystem;

// A plane in z = 0 (100 x 100, uv 0 to 50) seen from above at an angle (it fills the view), lit
// by a uniform sky of radiance `sky`.
Scene skyPlane(const Material& m, const std::string& algorithm, const Vec3& sky, int samples) {
  Scene s = testing::planeScene(testing::writePlaneObj("envplane", 50.0f, 0.0f, 50.0f), algorithm,
                                m, Vec3(0.0f, 0.0f, -1.0f), "envplane");
  s.lights.clear();
  EnvironmentDecl e;
  e.colour = sky;
  e.up = Vec3(0.0f, 0.0f, 1.0f);
  s.environment = e;
  s.render.lightSamples = samples;
  s.camera.position = {0.0f, -2.0f, 3.0f};
  s.camera.lookAt = Vec3(0.0f);
  s.camera.width = 40, s.camera.height = 30, s.camera.spp = 4;
  return s;
}

Image render(const Scene& scene, uint64_t seed = 1) {
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(scene, times);
  RenderCounters counters;
  return renderFrame(ctx, {.spp = scene.camera.spp, .seed = seed, .progress = false}, counters);
}

// The mean of channel c over the pixels that see the plane, and the RMS of their relative error
// against `exact`.
struct PlaneFigures {
  double mean = 0.0, rmsError = 0.0;
  int pixels = 0;
};
PlaneFigures planeFigures(const Image& img, int c, double exact) {
  PlaneFigures f;
  double sq = 0.0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      if (!(img.at(x, y, FilmLayout::DepthZ) > 0.0f)) continue;
      const double v = img.at(x, y, FilmLayout::R + c);
      f.mean += v;
      sq += (v / exact - 1.0) * (v / exact - 1.0);
      ++f.pixels;
    }
  f.mean /= std::max(f.pixels, 1);
  f.rmsError = std::sqrt(sq / std::max(f.pixels, 1));
  return f;
}

// meso's diffuse term is kd (L.N) E for a light of irradiance E at normal incidence (no 1 / pi), so
// a sky of radiance L, whose irradiance on an unoccluded plane is pi L, gives kd pi L. With the
// map's up along the plane's normal the plane's horizon is the map's equator, an edge of the
// sample strata; a tilted map cuts them, the general case.
TEST(EnvironmentRender, DiffusePlaneUnderAUniformSkyIsKdPiL) {
  Material m;
  m.ka = Vec3(0.0f);
  m.kd = Vec3(0.6f, 0.4f, 0.2f);
  m.ks = Vec3(0.0f);
  const Vec3 sky(0.3f, 0.5f, 0.7f);
  for (const Vec3 up : {Vec3(0.0f, 0.0f, 1.0f), glm::normalize(Vec3(0.4f, 0.3f, 1.0f))}) {
    Scene at64 = skyPlane(m, "auto", sky, 64), at16 = skyPlane(m, "auto", sky, 16);
    at64.environment->up = at16.environment->up = up;
    const Image i64 = render(at64), i16 = render(at16);
    ASSERT_TRUE(i64.allFinite());
    for (int c = 0; c < 3; ++c) {
      const double exact = m.kd[c] * kPi * sky[c];
      const PlaneFigures f64 = planeFigures(i64, c, exact), f16 = planeFigures(i16, c, exact);
      ASSERT_EQ(f64.pixels, i64.width * i64.height);
      std::printf(
          "[ figure ] up (%.2f, %.2f, %.2f), channel %d: mean %+.4f%% from kd pi L at 64 "
          "samples, %+.4f%% at 16; per-pixel RMS error %.3f%% at 16, %.3f%% at 64 (ratio "
          "%.2f; 1/sqrt(N) gives 2)\n",
          up.x, up.y, up.z, c, 100.0 * (f64.mean / exact - 1.0), 100.0 * (f16.mean / exact - 1.0),
          100.0 * f16.rmsError, 100.0 * f64.rmsError, f16.rmsError / f64.rmsError);
      EXPECT_NEAR(f64.mean / exact, 1.0, 0.005);
      EXPECT_NEAR(f16.mean / exact, 1.0, 0.005);
      EXPECT_LT(f64.rmsError, 0.02);  // each pixel, not only the mean
      // The error shrinks at least as fast as 1 / sqrt(N) (the stratified directions do better).
      EXPECT_GT(f16.rmsError / f64.rmsError, 1.8);
      EXPECT_GT(f64.rmsError, 0.0);  // light sampling noise is there to shrink
    }
  }
}

// A sky that is black but for one small texel of radiance Ls lights the scene as a directional
// light from that texel with the irradiance Ls * (its solid angle): relief, shadows and all, with
// every renderer.
TEST(EnvironmentRender, OneBrightTexelLightsLikeADirectionalLight) {
  const int w = 512, h = 256, sx = 300, sy = 60;  // the sun 42 degrees from the zenith
  Image map(w, h, {"R", "G", "B"});
  const float Ls = 5000.0f;
  for (int k = 0; k < 3; ++k) map.at(sx, sy, k) = Ls;
  const fs::path file = testing::ProcessTemporaries::add(
      fs::temp_directory_path() / ("meso_env_sun_" + std::to_string(::getpid()) + ".exr"));
  writeExr(file, map);
  Material m;
  m.ka = Vec3(0.0f);
  m.kd = Vec3(0.7f);
  m.ks = Vec3(0.2f);
  m.relief = {testing::noiseLevel(0.02f, 3.0f)};
  for (const char* algorithm : {"brdf", "redistribution", "displacement"}) {
    Scene env = skyPlane(m, algorithm, Vec3(1.0f), 4);
    env.environment->file = file;
    env.environment->rotation = 25.0f;
    Scene sun = env;
    sun.environment.reset();
    const double solidAngle =
        (2.0 * kPi / w) * (std::cos(kPi * sy / h) - std::cos(kPi * (sy + 1) / h));
    const EnvironmentMap probe(map, *env.environment);
    Light l;
    l.direction = -probe.direction(Vec2((sx + 0.5f) / w, (sy + 0.5f) / h));
    l.intensity = static_cast<float>(Ls * solidAngle);
    sun.lights = {l};
    const Image a = render(env), b = render(sun);
    double sa = 0.0, sb = 0.0;
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x)
        sa += a.at(x, y, FilmLayout::G), sb += b.at(x, y, FilmLayout::G);
    std::printf("[ figure ] %s: sun texel %.5f, directional %.5f (%+.3f%%)\n", algorithm, sa, sb,
                100.0 * (sa / sb - 1.0));
    EXPECT_GT(sb, 0.0);
    EXPECT_NEAR(sa / sb, 1.0, 0.01) << algorithm;
  }
}

// The surface is opaque: light from below the macro surface's horizon reaches nothing, whatever
// the renderer's normals face (a tilted bump normal would otherwise catch it from under an open
// plane). A sky lit only below the horizon leaves the relief plane black with shadows off; the
// same map turned over lights it.
TEST(EnvironmentRender, LightFromBelowTheHorizonLightsNothing) {
  Image map(32, 16, {"R", "G", "B"});
  for (int y = 8; y < 16; ++y)
    for (int x = 0; x < 32; ++x)
      for (int k = 0; k < 3; ++k) map.at(x, y, k) = 1.0f;
  const fs::path file = testing::ProcessTemporaries::add(
      fs::temp_directory_path() / ("meso_env_below_" + std::to_string(::getpid()) + ".exr"));
  writeExr(file, map);
  Material m;
  m.ka = Vec3(0.0f);
  m.kd = Vec3(0.7f);
  m.ks = Vec3(0.3f);
  m.relief = {testing::noiseLevel(0.05f, 3.0f)};
  for (const char* algorithm : {"bump", "redistribution", "brdf", "auto"}) {
    Scene s = skyPlane(m, algorithm, Vec3(1.0f), 8);
    s.environment->file = file;
    s.render.shadows = false;
    const Image below = render(s);
    s.environment->up = Vec3(0.0f, 0.0f, -1.0f);
    const Image above = render(s);
    double sumBelow = 0.0, sumAbove = 0.0;
    for (int y = 0; y < below.height; ++y)
      for (int x = 0; x < below.width; ++x) {
        if (!(below.at(x, y, FilmLayout::DepthZ) > 0.0f)) continue;
        sumBelow += below.at(x, y, FilmLayout::G);
        sumAbove += above.at(x, y, FilmLayout::G);
      }
    EXPECT_EQ(sumBelow, 0.0) << algorithm;
    EXPECT_GT(sumAbove, 100.0) << algorithm;
  }
}

// Camera rays that miss see the environment (render.background only without one).
TEST(EnvironmentRender, RaysThatMissSeeTheEnvironment) {
  Scene s = skyPlane(Material{}, "auto", Vec3(0.2f, 0.4f, 0.8f), 4);
  s.render.background = Vec3(1.0f, 0.0f, 0.0f);
  s.camera.lookAt = Vec3(0.0f, -2.0f, 10.0f);  // straight up: the plane is behind the camera
  s.camera.up = Vec3(0.0f, 1.0f, 0.0f);
  const Image img = render(s);
  for (int c = 0; c < 3; ++c)
    EXPECT_FLOAT_EQ(img.at(7, 5, FilmLayout::R + c), s.environment->colour[c]);
  EXPECT_EQ(img.at(7, 5, FilmLayout::DepthZ), 0.0f);
}

Image renderWithThreads(const Scene& scene, int threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  return render(scene, 11);
}

TEST(EnvironmentRender, OneAndTwoThreadsGiveBitIdenticalImages) {
  Material m;
  m.relief = {testing::noiseLevel(0.02f, 3.0f)};
  Scene s = skyPlane(m, "auto", Vec3(0.4f, 0.5f, 0.6f), 8);
  Light sun;
  sun.direction = glm::normalize(Vec3(0.3f, 0.2f, -1.0f));
  s.lights = {sun};
  const Image one = renderWithThreads(s, 1), two = renderWithThreads(s, 2);
  ASSERT_EQ(one.pixels.size(), two.pixels.size());
  EXPECT_EQ(0,
            std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(float)));
  const Image other = render(s, 12);  // another seed draws other directions
  EXPECT_NE(0,
            std::memcmp(one.pixels.data(), other.pixels.data(), one.pixels.size() * sizeof(float)));
}

}  // namespace
}  // namespace meso
