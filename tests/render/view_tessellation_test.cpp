// Objects drawn undisplaced are tessellated by view (render.tessellation_rate 0, the default):
// curved faces split per frame until the limit surface is within the coarse tolerance of its
// chords, as the hybrid does where it raises nothing; objects of flat faces keep two triangles a
// face, built once; a rate of 1..64 keeps the uniform tessellation.
#include "meso/render/integrator.h"
#include "meso/render/film_layout.h"
#include "support/plane_scene.h"  // ProcessTemporaries

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <unistd.h>

namespace meso {
namespace {

namespace fs = std::filesystem;

// The Catmull-Clark torus of scenes/torus.obj (96 faces, about 2.6 units across) seen from
// `distance` along a view 30 degrees above its plane, lit by ambient light alone on a black
// background: a pixel's red is the share of its samples that hit it.
Scene torusScene(float distance) {
  Scene scene;
  scene.file = fs::path(MESO_SOURCE_DIR) / "scenes/default.toml";
  scene.camera.position = distance * glm::normalize(Vec3(0.0f, 0.5f, 0.866f));
  scene.camera.lookAt = Vec3(0.0f);
  scene.camera.fovY = 40.0f;
  scene.camera.width = 160;
  scene.camera.height = 96;
  scene.camera.spp = 16;
  Light light;
  light.direction = glm::normalize(Vec3(-0.5f, -1.0f, -0.6f));
  light.intensity = 0.0f;
  scene.lights = {light};
  Material m;
  m.ka = Vec3(1.0f);
  m.kd = Vec3(0.0f);
  m.ks = Vec3(0.0f);
  scene.materials = {m};
  Object o;
  o.mesh = fs::path(MESO_SOURCE_DIR) / "scenes/torus.obj";
  o.scheme = SubdivisionScheme::CatmullClark;
  scene.objects = {o};
  scene.render.background = Vec3(0.0f);
  scene.render.shadows = false;
  return scene;
}

struct Drawn {
  double coverage = 0.0;  // pixels' worth of samples that hit the torus
  size_t triangles = 0;
  bool byView = false, viewDependent = false;
  Image image;
};

Drawn draw(const Scene& scene, uint64_t seed = 3) {
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(scene, times);
  RenderCounters counters;
  Drawn d;
  d.image = renderFrame(ctx, {scene.camera.spp, seed, false}, counters);
  for (int y = 0; y < d.image.height; ++y)
    for (int x = 0; x < d.image.width; ++x) d.coverage += d.image.at(x, y, FilmLayout::R);
  d.triangles = ctx.numTriangles();
  d.byView = ctx.objects.at(0).byView;
  d.viewDependent = ctx.viewDependent();
  return d;
}

// The torus's coverage by view agrees with a uniform rate of 32 to 0.1% (0.05% measured), where
// rate 2 misses 1.3% of it (so the test sees a coarse tessellation); by view it takes a tenth of
// rate 32's triangles, and a sixth of those from 8 times as far.
TEST(ViewTessellation, CurvedObjectsDrawnUndisplacedFollowTheLimitSurfaceByView) {
  Scene scene = torusScene(5.0f);
  ASSERT_EQ(scene.render.tessellationRate, 0) << "by view is the default";
  const Drawn view = draw(scene);
  EXPECT_TRUE(view.byView);
  EXPECT_TRUE(view.viewDependent);
  EXPECT_TRUE(view.image.allFinite());
  scene.render.tessellationRate = 32;
  const Drawn fine = draw(scene);
  EXPECT_FALSE(fine.byView);
  EXPECT_FALSE(fine.viewDependent);
  EXPECT_EQ(fine.triangles, 96u * 2u * 32u * 32u);
  scene.render.tessellationRate = 2;
  const Drawn coarse = draw(scene);
  ASSERT_GT(fine.coverage, 1500.0) << "the torus fills part of the frame";
  EXPECT_NEAR(view.coverage / fine.coverage, 1.0, 0.001);
  EXPECT_LT(coarse.coverage / fine.coverage, 0.99);
  EXPECT_LT(view.triangles, fine.triangles / 5);
  EXPECT_GT(view.triangles, coarse.triangles);

  scene.render.tessellationRate = 0;
  scene.camera.position *= 8.0f;
  const Drawn far = draw(scene);
  EXPECT_LT(far.triangles, view.triangles / 4);
  EXPECT_GE(far.triangles, 96u * 2u) << "at least two triangles a face in view";
  EXPECT_TRUE(far.image.allFinite());
}

// The micropolygon cap bounds what is tessellated by view, coarsening the farthest first, with a
// warning that names the mesh.
TEST(ViewTessellation, TheMicropolygonCapBoundsIt) {
  Scene scene = torusScene(5.0f);
  const size_t asked = draw(scene).triangles;
  scene.render.maxMicropolygons = static_cast<int64_t>(asked / 3);
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(scene, times);
  EXPECT_LE(ctx.numTriangles(), asked / 3);
  EXPECT_GE(ctx.numTriangles(), 96u * 2u);
  bool named = false;
  for (const std::string& w : ctx.warnings.list())
    named = named ||
            (w.find("torus.obj") != std::string::npos && w.find("coarsened") != std::string::npos);
  EXPECT_TRUE(named);
}

// An object whose every face is flat keeps two triangles a face, made once (not per frame).
TEST(ViewTessellation, FlatObjectsKeepTwoTrianglesAFaceBuiltOnce) {
  Scene scene = torusScene(5.0f);
  const fs::path file = meso::testing::ProcessTemporaries::add(
      fs::temp_directory_path() / (std::to_string(::getpid()) + "_meso_view_grid.obj"));
  {
    std::ofstream out(file);
    for (int j = 0; j <= 4; ++j)
      for (int i = 0; i <= 4; ++i) out << "v " << i - 2 << " 0 " << j - 2 << "\n";
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        const int a = j * 5 + i + 1;
        out << "f " << a << " " << a + 5 << " " << a + 6 << " " << a + 1 << "\n";
      }
  }
  scene.objects[0].mesh = file;
  scene.objects[0].scheme = SubdivisionScheme::Bilinear;
  const Drawn grid = draw(scene);
  EXPECT_FALSE(grid.byView);
  EXPECT_FALSE(grid.viewDependent);
  EXPECT_EQ(grid.triangles, 16u * 2u);
  EXPECT_GT(grid.coverage, 1000.0);
}

// Same scene, same seed: the same image by view whatever the thread count.
TEST(ViewTessellation, OneAndTwoThreadsGiveBitIdenticalImages) {
  Scene scene = torusScene(5.0f);
  scene.camera.width = 48;
  scene.camera.height = 32;
  scene.camera.spp = 4;
  const auto render = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return draw(scene, 11);
  };
  const Drawn one = render(1), two = render(2);
  ASSERT_EQ(one.image.pixels.size(), two.image.pixels.size());
  EXPECT_EQ(one.triangles, two.triangles);
  EXPECT_EQ(0, std::memcmp(one.image.pixels.data(), two.image.pixels.data(),
                           one.image.pixels.size() * sizeof(float)));
}

// The camera nearly touching the torus, and 10^5 units away: finite images, and a bounded mesh.
TEST(ViewTessellation, ExtremeDistancesGiveFiniteImages) {
  for (float distance : {1.02f, 1e5f}) {
    Scene scene = torusScene(distance);
    scene.camera.lookAt = Vec3(1.0f, 0.0f, 0.0f);
    scene.camera.spp = 2;
    const Drawn d = draw(scene);
    EXPECT_TRUE(d.image.allFinite()) << distance;
    EXPECT_LE(d.triangles, size_t{80'000'000}) << distance;
  }
}

}  // namespace
}  // namespace meso
