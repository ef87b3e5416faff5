// Renders analytic scenes with known intensity, and checks determinism across thread counts.
#include "meso/core/error.h"
#include "meso/render/film_layout.h"
#include "meso/render/integrator.h"
#include "meso/render/shading.h"

#include "support/plane_scene.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <filesystem>
#include <cstring>
#include <fstream>

#include <unistd.h>

namespace meso {
namespace {

namespace fs = std::filesystem;

fs::path writeQuadObj(const std::string& name, float half) {
  // One file per process: ctest runs tests in parallel processes.
  const fs::path file = meso::testing::ProcessTemporaries::add(
      fs::temp_directory_path() / (std::to_string(::getpid()) + "_" + name));
  std::ofstream out(file);
  out << "v " << -half << " " << -half << " 0\nv " << half << " " << -half << " 0\n"
      << "v " << half << " " << half << " 0\nv " << -half << " " << half << " 0\nf 1 2 3 4\n";
  return file;
}

Scene planeScene(const Vec3& lightTravel) {
  Scene scene;
  scene.camera.position = {0.3f, -0.2f, 5.0f};
  scene.camera.lookAt = {0.0f, 0.0f, 0.0f};
  scene.camera.width = 48;
  scene.camera.height = 32;
  scene.camera.spp = 3;
  Light light;
  light.direction = glm::normalize(lightTravel);
  light.intensity = 1.5f;
  scene.lights = {light};
  Material m;
  m.ka = Vec3(0.0f);
  m.kd = {0.5f, 0.25f, 0.125f};
  m.ks = Vec3(0.0f);
  scene.materials = {m};
  Object o;
  o.mesh = writeQuadObj("meso_integrator_plane.obj", 50.0f);
  o.scheme = SubdivisionScheme::Bilinear;
  scene.objects = {o};
  scene.render.tessellationRate = 2;
  return scene;
}

// One directional light, a plane facing it, kd only: every pixel is kd * intensity * (L.N).
TEST(Integrator, FlatPlaneUnderDirectionalLightHasExactIntensity) {
  const Scene scene = planeScene({-0.6f, 0.0f, -0.8f});
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(scene, times);
  RenderCounters counters;
  const Image img = renderFrame(ctx, {scene.camera.spp, 7, false}, counters);
  ASSERT_TRUE(img.allFinite());
  EXPECT_EQ(counters.rays.load(), 48 * 32 * 3);
  // No relief and the plane fills the view: every sample is smooth shading.
  for (int k = 0; k < kSampleRenderers; ++k)
    EXPECT_EQ(counters.shares[k].load(),
              k == static_cast<int>(SampleRenderer::Smooth) ? 48 * 32 * 3 * kShareUnit : 0)
        << kSampleRendererNames[k];
  const Vec3 expected = scene.materials[0].kd * 1.5f * 0.8f;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(img.at(x, y, FilmLayout::R + c), expected[c], 2e-6f) << x << "," << y;
      EXPECT_NEAR(img.at(x, y, FilmLayout::NormalZ), 1.0f, 1e-6f);
      EXPECT_GT(img.at(x, y, FilmLayout::DepthZ), 4.9f);
    }
}

// A relief plane seen whole by one fixed renderer: its samples and the background's make up all
// the samples, exactly.
TEST(Integrator, SampleSharesOfAFixedRendererAndTheBackground) {
  Material m;
  m.relief = {testing::noiseLevel(0.01f, 4.0f)};
  Scene scene = testing::planeScene(testing::writePlaneObj("shares", 1.0f, 0.0f, 4.0f), "bump", m,
                                    Vec3(0.0f, 0.3f, -1.0f), "shares");
  scene.camera.position = {0.0f, -3.0f, 3.0f};
  scene.camera.lookAt = Vec3(0.0f);
  scene.camera.width = 32, scene.camera.height = 24, scene.camera.spp = 2;
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(scene, times);
  RenderCounters counters;
  renderFrame(ctx, {scene.camera.spp, 1, false}, counters);
  const int64_t bump = counters.shares[static_cast<int>(SampleRenderer::Bump)].load();
  const int64_t background = counters.shares[static_cast<int>(SampleRenderer::Background)].load();
  EXPECT_GT(bump, 0);
  EXPECT_GT(background, 0);
  EXPECT_EQ(bump + background, counters.rays.load() * kShareUnit);
}

TEST(Integrator, LightFromBehindThePlaneGivesAmbientOnly) {
  Scene scene = planeScene({0.0f, 0.0f, 1.0f});
  scene.materials[0].ka = Vec3(0.1f, 0.2f, 0.3f);
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(scene, times);
  RenderCounters counters;
  const Image img = renderFrame(ctx, {1, 0, false}, counters);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < 3; ++c)
        ASSERT_FLOAT_EQ(img.at(x, y, FilmLayout::R + c), scene.materials[0].ka[c]);
}

TEST(Shading, BlinnPhongHighlightAtMirrorConfiguration) {
  Material m;
  m.ka = Vec3(0.0f);
  m.kd = Vec3(0.0f);
  m.ks = Vec3(1.0f);
  m.phong = 50.0f;
  Light light;
  light.direction = glm::normalize(Vec3(-1.0f, 0.0f, -1.0f));  // L = (1,0,1)/sqrt2
  const Vec3 N(0.0f, 0.0f, 1.0f);
  const Light lights[] = {light};
  // Mirror direction: H = N, so (H.N)^n = 1.
  EXPECT_NEAR(shadeLocal(m, lights, Vec3(0.0f), N, glm::normalize(Vec3(-1.0f, 0.0f, 1.0f))).x, 1.0f,
              1e-6f);
  // V = N: H is halfway between L and N, at 22.5 degrees: cos(22.5)^50.
  EXPECT_NEAR(shadeLocal(m, lights, Vec3(0.0f), N, N).x, std::pow(std::cos(kPi / 8.0f), 50.0f),
              1e-5f);
}

TEST(Shading, PointLightFallsOffWithInverseSquare) {
  Light light;
  light.type = LightType::Point;
  light.position = {0.0f, 0.0f, 2.0f};
  light.intensity = 8.0f;
  EXPECT_NEAR(sampleLight(light, Vec3(0.0f)).radiance.x, 2.0f, 1e-6f);
  light.position = Vec3(0.0f);
  const LightSample s = sampleLight(light, Vec3(0.0f));  // the light touches the point
  EXPECT_TRUE(isFinite(s.radiance));
  EXPECT_TRUE(isFinite(s.L));
}

Scene torusScene() {
  Scene scene;
  scene.file = fs::path(MESO_SOURCE_DIR) / "scenes/default.toml";
  scene.camera.position = {0.0f, 2.0f, 4.0f};
  scene.camera.width = 40;
  scene.camera.height = 24;
  Light light;
  light.direction = glm::normalize(Vec3(-0.5f, -1.0f, -0.6f));
  scene.lights = {light};
  Material m;
  m.ks = Vec3(0.3f);
  m.phong = 30.0f;
  scene.materials = {m};
  Object o;
  o.mesh = fs::path(MESO_SOURCE_DIR) / "scenes/torus.obj";
  scene.objects = {o};
  scene.render.tessellationRate = 3;
  return scene;
}

Image renderWithThreads(const Scene& scene, int threads, uint64_t seed) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(scene, times);
  RenderCounters counters;
  return renderFrame(ctx, {5, seed, false}, counters);
}

TEST(Integrator, OneAndTwoThreadsGiveBitIdenticalImages) {
  const Scene scene = torusScene();
  const Image one = renderWithThreads(scene, 1, 11);
  const Image two = renderWithThreads(scene, 2, 11);
  ASSERT_TRUE(one.allFinite());
  ASSERT_EQ(one.pixels.size(), two.pixels.size());
  EXPECT_EQ(0,
            std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(float)));
  // The seed matters (the jitter moves silhouette samples), so the comparison above is not vacuous.
  const Image other = renderWithThreads(scene, 2, 12);
  EXPECT_NE(0,
            std::memcmp(one.pixels.data(), other.pixels.data(), one.pixels.size() * sizeof(float)));
}

// RenderOptions::traceOnly (tools/bench_frame's baseline): the same camera rays and closest hits
// as a full render, so depth.Z is identical bit for bit, and nothing shaded: the beauty is black.
TEST(Integrator, TraceOnlyFindsTheSameHitsAndShadesNothing) {
  const Scene scene = torusScene();
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(scene, times);
  RenderCounters counters;
  RenderOptions full{5, 3, false};
  RenderOptions trace = full;
  trace.traceOnly = true;
  const Image a = renderFrame(ctx, full, counters), b = renderFrame(ctx, trace, counters);
  const int depth = FilmLayout::DepthZ, red = FilmLayout::R;
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  int hits = 0, shaded = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      EXPECT_EQ(a.at(x, y, depth), b.at(x, y, depth)) << x << ", " << y;
      EXPECT_EQ(b.at(x, y, red), 0.0f);
      hits += a.at(x, y, depth) > 0.0f;
      shaded += a.at(x, y, red) > 0.0f;
    }
  EXPECT_GT(hits, a.width * a.height / 10);  // the torus is in view
  // The full render lights most of those hits, so the black beauty above is trace-only's doing.
  EXPECT_GT(shaded, hits / 2);
  EXPECT_EQ(counters.rays.load(), 2 * int64_t{5} * a.width * a.height) << "both frames counted";
}

// RenderOptions::window (meso render --crop): the film is the window, and each of its pixels is
// the whole image's pixel bit for bit, in every channel; a window reaching outside the image is an
// error.
TEST(Integrator, WindowIsTheSameBitsAsTheWholeImage) {
  const Scene scene = torusScene();
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(scene, times);
  RenderCounters counters;
  const Image whole = renderFrame(ctx, {.spp = 5, .seed = 3, .progress = false}, counters);
  // Not aligned with the 16-pixel tiles, and wider than one.
  const PixelWindow w{.x0 = 5, .y0 = 3, .x1 = 30, .y1 = whole.height - 2};
  const Image part =
      renderFrame(ctx, {.spp = 5, .seed = 3, .progress = false, .window = w}, counters);
  ASSERT_EQ(part.width, w.width());
  ASSERT_EQ(part.height, w.height());
  int hits = 0;
  for (int y = 0; y < part.height; ++y)
    for (int x = 0; x < part.width; ++x) {
      for (int c = 0; c < FilmLayout::kChannels; ++c)
        ASSERT_EQ(part.at(x, y, c), whole.at(w.x0 + x, w.y0 + y, c))
            << FilmLayout::kNames[c] << " " << x << "," << y;
      hits += part.at(x, y, FilmLayout::DepthZ) > 0.0f;
    }
  EXPECT_GT(hits, 20) << "the torus is in the window";
  for (const PixelWindow bad : {PixelWindow{-1, 0, 4, 4}, PixelWindow{0, 0, whole.width + 1, 4},
                                PixelWindow{4, 4, 4, 8}, PixelWindow{0, 5, 4, 2}})
    EXPECT_THROW(renderFrame(ctx, {.spp = 1, .progress = false, .window = bad}, counters), Error);
}

}  // namespace
}  // namespace meso
