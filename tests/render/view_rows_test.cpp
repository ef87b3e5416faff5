// Only the table entries a scene needs (docs/tables.md): the theta_V a scene's frames see on a flat
// surface, against every pixel's ray; images rendered with the tables built on those rows
// only are the whole tables' images, bit for bit.
#include "meso/geometry/limit_surface.h"
#include "meso/render/film_layout.h"
#include "meso/render/integrator.h"
#include "meso/render/render_context.h"
#include "meso/render/view_rows.h"
#include "meso/scene/camera.h"
#include "meso/scene/mesh_io.h"

#include "support/plane_scene.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

namespace meso {
namespace {

// A 40 x 40 ground in z = 0 with unit-speed uv and two noise levels, seen from `eye`.
Scene groundScene(const std::string& algorithm, const Vec3& eye, const Vec3& target) {
  Material m;
  m.kd = Vec3(0.7f);
  m.ks = Vec3(0.2f);
  m.phong = 20.0f;
  m.relief = {testing::noiseLevel(0.02f, 2.0f, 3), testing::noiseLevel(0.004f, 16.0f, 2)};
  Scene s = testing::planeScene(testing::writePlaneObj("rows", 20.0f, 0.0f, 40.0f), algorithm, m,
                                Vec3(0.4f, 0.5f, -0.7f), "rows");
  s.camera.position = eye;
  s.camera.lookAt = target;
  s.camera.width = 64;
  s.camera.height = 36;
  s.camera.fovY = 40.0f;
  s.camera.spp = 1;
  s.render.tables.raysPerView = 256;
  s.render.tables.azimuths = 16;
  s.render.tables.shadowRays = 32;
  return s;
}

// The smallest and largest angle between the ground's normal and the direction to the eye over
// every ray through a fine grid of film positions that meets the ground.
std::pair<float, float> angleOverPixels(const Scene& s) {
  const Camera camera(s.camera);
  float lo = 10.0f, hi = -1.0f;
  const int n = 400;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const Ray r = camera.generateRay(static_cast<float>(i) * s.camera.width / n,
                                       static_cast<float>(j) * s.camera.height / n);
      if (!(r.direction.z < 0.0f)) continue;
      const Vec3 p = r.origin - r.origin.z / r.direction.z * r.direction;
      if (std::abs(p.x) > 20.0f || std::abs(p.y) > 20.0f) continue;
      const float theta = std::acos(std::min(-r.direction.z, 1.0f));
      lo = std::min(lo, theta), hi = std::max(hi, theta);
    }
  return {lo, hi};
}

ViewAngles anglesOf(const Scene& s, const RenderContext& ctx) {
  std::vector<ScreenMetric> screens;
  for (const CameraSettings& c : sceneCameras(s)) screens.push_back(Camera(c).screen());
  const LimitSurface* surface = &ctx.objects[0].surface;
  return coarsestViewAngles(std::span(&surface, 1), ctx.reliefs[0], screens, 0.0f);
}

TEST(ViewRows, FlatGroundAnglesAreThoseOfItsPixels) {
  // Low over the ground looking at the far edge, and straight down over it (the eye's foot in
  // view: theta_V 0 is seen).
  for (const auto& [eye, target] : {std::pair{Vec3(0, -19, 2.5f), Vec3(0, 0, 0)},
                                    std::pair{Vec3(3, -4, 1.5f), Vec3(3, 20, 0.5f)},
                                    std::pair{Vec3(1, 2, 30), Vec3(1, 2.5f, 0)}}) {
    const Scene s = groundScene("brdf", eye, target);
    PrepareTimes times;
    const RenderContext ctx = prepareRenderContext(s, times, {.buildFrame = false});
    const ViewAngles a = anglesOf(s, ctx);
    const auto [lo, hi] = angleOverPixels(s);
    ASSERT_FALSE(a.all);
    // The bounds hold every pixel's angle, and are the pixels' own to the half-degree margin and
    // the grid's spacing.
    const float deg = kPi / 180.0f;
    EXPECT_LE(a.lo, lo);
    EXPECT_GE(a.lo, lo - 0.6f * deg) << "eye " << eye.x << " " << eye.y << " " << eye.z;
    EXPECT_GE(a.hi, hi);
    EXPECT_LE(a.hi, hi + 0.6f * deg) << "eye " << eye.x << " " << eye.y << " " << eye.z;
  }
}

// The same ground as 40 x 40 unit faces: faces no frame sees are skipped before their corners are
// evaluated, and the union of the rest is the one quad's view, at every eye of the test above.
// A 40 x 40 grid of unit faces in z = 0, with vertex (i, j) (0-based, -1: none) raised by 0.5: its
// four faces are twisted, not affine.
LimitSurface groundGrid(int raisedI = -1, int raisedJ = -1) {
  std::string obj;
  for (int j = 0; j <= 40; ++j)
    for (int i = 0; i <= 40; ++i)
      obj += fmt::format("v {} {} {}\nvt {} {}\n", i - 20, j - 20,
                         i == raisedI && j == raisedJ ? 0.5 : 0.0, i, j);
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 40; ++i) {
      const int a = j * 41 + i + 1;
      obj += fmt::format("f {0}/{0} {1}/{1} {2}/{2} {3}/{3}\n", a, a + 1, a + 42, a + 41);
    }
  return LimitSurface(parseControlMesh(obj, "grid.obj"), SubdivisionScheme::Bilinear);
}

TEST(ViewRows, GroundOfManyFacesHasTheOneQuadsAngles) {
  const LimitSurface grid = groundGrid();
  ASSERT_EQ(grid.numFaces(), 1600);
  for (const auto& [eye, target] :
       {std::pair{Vec3(0, -19, 2.5f), Vec3(0, 0, 0)},
        std::pair{Vec3(3, -4, 1.5f), Vec3(3, 20, 0.5f)}, std::pair{Vec3(-2, 1, 4), Vec3(-6, 9, 0)},
        std::pair{Vec3(1, 2, 30), Vec3(1, 2.5f, 0)}}) {
    const Scene s = groundScene("brdf", eye, target);
    PrepareTimes times;
    const RenderContext ctx = prepareRenderContext(s, times, {.buildFrame = false});
    const ScreenMetric screen = Camera(s.camera).screen();
    const LimitSurface *quad = &ctx.objects[0].surface, *many = &grid;
    for (const float bound : {0.0f, 0.3f}) {
      const ViewAngles a =
          coarsestViewAngles(std::span(&quad, 1), ctx.reliefs[0], std::span(&screen, 1), bound);
      const ViewAngles b =
          coarsestViewAngles(std::span(&many, 1), ctx.reliefs[0], std::span(&screen, 1), bound);
      ASSERT_FALSE(a.all);
      ASSERT_FALSE(b.all);
      EXPECT_NEAR(b.lo, a.lo, 1e-4f) << "eye " << eye.x << " " << eye.y << " " << eye.z;
      EXPECT_NEAR(b.hi, a.hi, 1e-4f) << "eye " << eye.x << " " << eye.y << " " << eye.z;
    }
  }
}

TEST(ViewRows, TablesOnTheFramesRowsRenderTheWholeTablesImage) {
  for (const char* algorithm : {"auto", "brdf", "redistribution"}) {
    Scene s = groundScene(algorithm, Vec3(0, -19, 2.5f), Vec3(0, 0, 0));
    Scene whole = s;
    whole.render.tables.frameViews = false;
    PrepareTimes times;
    const RenderContext a = prepareRenderContext(s, times);
    const RenderContext b = prepareRenderContext(whole, times);
    const ViewRows& rows = a.reliefs[0].metrics[0].levels[0].brdf.viewRows();
    EXPECT_FALSE(rows.all()) << "a view of the ground from 2.5 units up sees no theta_V near 0";
    EXPECT_GT(rows.first, 4);
    // The finer level's rows reach further down (the coarser relief tilts its frames), but not to
    // 0.
    const ViewRows& finer = a.reliefs[0].metrics[0].levels[1].brdf.viewRows();
    EXPECT_FALSE(finer.all());
    EXPECT_LT(finer.first, rows.first);
    EXPECT_TRUE(b.reliefs[0].metrics[0].levels[0].brdf.viewRows().all());
    RenderCounters counters;
    const Image ia = renderFrame(a, {s.camera.spp, 3, false}, counters);
    const Image ib = renderFrame(b, {s.camera.spp, 3, false}, counters);
    double sum = 0.0;
    for (int y = 0; y < ia.height; ++y)
      for (int x = 0; x < ia.width; ++x)
        for (int c : {FilmLayout::R, FilmLayout::G, FilmLayout::B}) {
          ASSERT_EQ(ia.at(x, y, c), ib.at(x, y, c)) << algorithm << " at " << x << ", " << y;
          sum += ia.at(x, y, c);
        }
    EXPECT_GT(sum, 0.0);
  }
}

}  // namespace
}  // namespace meso

namespace meso {
namespace {

// Only faces a frame may see are tested for flatness: a curved face behind the eye leaves the
// ground's angles bounded (the flat ground's), while one in view makes them all.
TEST(ViewRows, OnlyCurvedFacesInViewUnboundTheAngles) {
  const Scene s = groundScene("brdf", Vec3(3, -4, 1.5f), Vec3(3, 20, 0.5f));
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(s, times, {.buildFrame = false});
  const ScreenMetric screen = Camera(s.camera).screen();
  const LimitSurface flat = groundGrid(), behind = groundGrid(1, 1), ahead = groundGrid(23, 30);
  const auto angles = [&](const LimitSurface& g) {
    const LimitSurface* p = &g;
    return coarsestViewAngles(std::span(&p, 1), ctx.reliefs[0], std::span(&screen, 1), 0.3f);
  };
  const ViewAngles a = angles(flat), b = angles(behind), c = angles(ahead);
  ASSERT_FALSE(a.all);
  ASSERT_FALSE(b.all);
  EXPECT_EQ(b.lo, a.lo);
  EXPECT_EQ(b.hi, a.hi);
  EXPECT_TRUE(c.all);
}

}  // namespace
}  // namespace meso
