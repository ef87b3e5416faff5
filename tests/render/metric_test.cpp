// The surface's own metric (docs/metric.md): the same world relief on a plane whose uv is scaled,
// stretched or sheared gives the same BRDF and redistribution images; geometry and shading agree
// on disp per level; heights are centred on their midlevel.
#include "meso/render/film_layout.h"
#include "meso/render/integrator.h"
#include "meso/appearance/material_tables.h"
#include "meso/render/surface_shader.h"
#include "meso/render/tile_map.h"
#include "meso/core/rng.h"

#include <glm/gtc/matrix_transform.hpp>

#include "support/plane_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <utility>

namespace meso {
namespace {

// A 40 x 40 plane in z = 0 whose four corners carry the given uv.
std::filesystem::path writeQuad(const std::string& tag, const Vec2 uv[4]) {
  const std::filesystem::path file = testing::ProcessTemporaries::add(
      std::filesystem::temp_directory_path() /
      ("meso_metric_" + tag + "_" + std::to_string(::getpid()) + ".obj"));
  std::ofstream out(file);
  out << "v -20 -20 0\nv 20 -20 0\nv 20 20 0\nv -20 20 0\n";
  for (int k = 0; k < 4; ++k) out << "vt " << uv[k].x << " " << uv[k].y << "\n";
  out << "f 1/1 2/2 3/3 4/4\n";
  return file;
}

// The same world relief (2 periods per world unit, amplitude `amplitude`) whatever the uv: the
// tiling scale follows the uv's length per world unit.
Scene metricScene(const std::string& algorithm, const std::string& tag, const Vec2 uv[4],
                  float scale, float amplitude) {
  Material m;
  m.kd = Vec3(0.7f);
  m.ks = Vec3(0.2f);
  m.phong = 20.0f;
  m.relief = {testing::noiseLevel(amplitude, scale, 3)};
  Scene s =
      testing::planeScene(writeQuad(tag, uv), algorithm, m, Vec3(0.4f, 0.5f, -0.7f), "metric");
  s.camera.position = {0.0f, -19.0f, 2.5f};
  s.camera.lookAt = {0.0f, 0.0f, 0.0f};
  s.camera.width = 64;
  s.camera.height = 36;
  s.camera.fovY = 40.0f;
  s.camera.spp = 1;
  s.render.tables.raysPerView =
      512;  // small tables: the comparison is between metrics, same tables
  s.render.tables.azimuths = 16;
  return s;
}

// Mean red over bands of rows, counting pixels that hit the plane; bands with no such pixel (the
// sky above the horizon) are left out.
std::vector<double> bandMeans(const Scene& scene, int bands) {
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(scene, times);
  RenderCounters counters;
  const Image img = renderFrame(ctx, {scene.camera.spp, 3, false}, counters);
  EXPECT_TRUE(img.allFinite());
  std::vector<double> sum(bands, 0.0), count(bands, 0.0);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      if (!(img.at(x, y, FilmLayout::DepthZ) > 0.0f)) continue;
      sum[y * bands / img.height] += img.at(x, y, FilmLayout::R);
      count[y * bands / img.height] += 1.0;
    }
  std::vector<double> means;
  for (int b = 0; b < bands; ++b)
    if (count[b] > 0.0) means.push_back(sum[b] / count[b]);
  return means;
}

// uv 0..40 (unit speed), 0..40/12 and 0..1 (as Blender's primitive plane): before the tables knew
// the metric, brdf was 37% and redistribution 10% darker at 0..1.
TEST(Metric, ScaledUvGivesTheSameImages) {
  for (const char* algorithm : {"brdf", "redistribution"}) {
    std::vector<std::vector<double>> means;
    for (float length : {40.0f, 40.0f / 12.0f, 1.0f}) {
      const Vec2 uv[4] = {{0, 0}, {length, 0}, {length, length}, {0, length}};
      means.push_back(
          bandMeans(metricScene(algorithm, "scaled", uv, 2.0f * 40.0f / length, 0.03f), 3));
    }
    ASSERT_GE(means[0].size(), 2u);
    for (size_t k = 1; k < means.size(); ++k)
      for (size_t b = 0; b < means[0].size(); ++b)
        EXPECT_NEAR(means[k][b] / means[0][b], 1.0, 0.003)
            << algorithm << " uv scale " << k << " band " << b;
  }
}

// With the unit-metric tables of before, a plane whose uv runs 0..1 over 40 units saw a relief 40
// times steeper: its BRDF image is far from the unit-speed one unless the metric is used.
TEST(Metric, TablesFollowTheLengthPerU) {
  const Vec2 unit[4] = {{0, 0}, {40, 0}, {40, 40}, {0, 40}};
  const Vec2 one[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  Scene a = metricScene("brdf", "unit", unit, 2.0f, 0.03f);
  Scene b = metricScene("brdf", "one", one, 80.0f, 0.03f);
  PrepareTimes times;
  const RenderContext ca = prepareRenderContext(a, times,
                                                {.buildFrame = false, .keepHistograms = true}),
                      cb = prepareRenderContext(b, times,
                                                {.buildFrame = false, .keepHistograms = true});
  ASSERT_EQ(ca.reliefs[0].metrics.size(), 1u);
  ASSERT_EQ(cb.reliefs[0].metrics.size(), 1u);
  EXPECT_NEAR(ca.reliefs[0].metrics[0].lengthPerU, 1.0f, 1e-4f);
  EXPECT_NEAR(cb.reliefs[0].metrics[0].lengthPerU, 40.0f, 4e-3f);
  // Same world relief, same tile in tile units: identical histograms.
  const auto& ha = ca.reliefs[0].tables(0).distr;
  const auto& hb = cb.reliefs[0].tables(0).distr;
  double diff = 0.0;
  for (int k = 0; k < ha.resolution().thetaV; ++k)
    for (int i = 0; i < ha.resolution().thetaN; ++i)
      for (int j = 0; j < ha.resolution().phi; ++j)
        diff += std::abs(ha.mass(k, i, j) - hb.mass(k, i, j));
  EXPECT_LT(diff, 1e-3) << "summed over 16 slices of mass 1";
}

// Only what a frame needs: bump and displacement read no appearance tables, so none are built or
// loaded (the metric classes are still listed); the table renderers get one set per class.
TEST(Metric, OnlyTableRenderersGetTables) {
  const Vec2 unit[4] = {{0, 0}, {40, 0}, {40, 40}, {0, 40}};
  for (const char* algorithm : {"bump", "displacement", "brdf"}) {
    const Scene s = metricScene(algorithm, std::string("only_") + algorithm, unit, 2.0f, 0.03f);
    PrepareTimes times;
    const RenderContext ctx = prepareRenderContext(s, times, {.buildFrame = false});
    ASSERT_EQ(ctx.reliefs[0].metrics.size(), 1u) << algorithm;
    const bool tables = std::string(algorithm) == "brdf";
    EXPECT_EQ(ctx.reliefs[0].metrics[0].levels.size(), tables ? 1u : 0u) << algorithm;
    EXPECT_EQ(times.tablesBuilt + times.tablesFromCache, tables ? 1 : 0) << algorithm;
  }
}

// Faces without uv carry the relief on their own charts, and a triangle's chart has its own shape:
// a bilinear ground of 10-unit squares split into triangles along alternating diagonals (their
// right angles at different corners, as exporters triangulate) is one metric class, the identity
// shape at length 10 (the unit right triangle as every triangle's chart made sheared classes).
// Under Loop the same ground is curved in its parameterization (its vertices of valence 4 and 8
// are extraordinary) and has many classes.
TEST(Metric, TriangulatedGroundWithoutUvIsOneClass) {
  const std::filesystem::path file = testing::ProcessTemporaries::add(
      std::filesystem::temp_directory_path() /
      ("meso_metric_triangles_" + std::to_string(::getpid()) + ".obj"));
  {
    std::ofstream out(file);
    constexpr int kSide = 4;
    for (int j = 0; j <= kSide; ++j)
      for (int i = 0; i <= kSide; ++i) out << "v " << 10 * i - 20 << " " << 10 * j - 20 << " 0\n";
    for (int j = 0; j < kSide; ++j)
      for (int i = 0; i < kSide; ++i) {
        const int a = j * (kSide + 1) + i + 1, b = a + 1, c = a + kSide + 1, d = c + 1;
        if ((i + j) % 2 == 0)
          out << "f " << a << " " << b << " " << d << "\nf " << a << " " << d << " " << c << "\n";
        else
          out << "f " << a << " " << b << " " << c << "\nf " << b << " " << d << " " << c << "\n";
      }
  }
  Material m;
  m.relief = {testing::noiseLevel(0.03f, 2.0f, 3)};
  Scene s = testing::planeScene(file, "bump", m, Vec3(0.4f, 0.5f, -0.7f), "triangles");
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(s, times, {.buildFrame = false});
  ASSERT_EQ(ctx.reliefs[0].metrics.size(), 1u);
  EXPECT_NEAR(ctx.reliefs[0].metrics[0].lengthPerU, 10.0f, 1e-3f);
  EXPECT_TRUE(ctx.reliefs[0].metrics[0].shape.identity());
}

// A render's tables keep only the layout of their histograms (3 MB each at the default resolution;
// no renderer reads the masses once the BRDF, redistribution and self-shadowing tables are built);
// `meso tables` (keepHistograms) keeps the masses for its plots. The BRDF is the same either way.
TEST(Metric, RenderContextsKeepNoHistogramMasses) {
  const Vec2 unit[4] = {{0, 0}, {40, 0}, {40, 40}, {0, 40}};
  const Scene s = metricScene("brdf", "masses", unit, 2.0f, 0.03f);
  PrepareTimes times;
  const RenderContext lean = prepareRenderContext(s, times, {.buildFrame = false}),
                      kept = prepareRenderContext(s, times,
                                                  {.buildFrame = false, .keepHistograms = true});
  const LevelTables &a = lean.reliefs[0].tables(0), &b = kept.reliefs[0].tables(0);
  EXPECT_TRUE(a.distr.toData(false).empty());
  EXPECT_EQ(b.distr.toData(false).size(), b.distr.numBins());
  EXPECT_EQ(a.distr.resolution().thetaN, b.distr.resolution().thetaN) << "the layout stays";
  EXPECT_EQ(a.distr.resolution().phiV, b.distr.resolution().phiV);
  EXPECT_EQ(a.distr.thetaVMax(), b.distr.thetaVMax());
  EXPECT_EQ(a.brdf.data(), b.brdf.data());
  EXPECT_EQ(a.bytes, b.bytes);
}

// Stretched (|P_u| = 3 |P_v|) and sheared (45 degrees) uv: the table renderers agree with full
// displacement, which reads no tables, on the same uv, band by band of rows. Measured: brdf (and
// auto, which is brdf at this distance) +0.8% and +0.1% stretched, +3.3% and +0.9% sheared;
// redistribution +0.5%, -0.6%, +2.9%, +0.9%. Tables built as if the uv were unit speed (metricOf
// returning the identity class) put brdf at -1.9% and -2.3% stretched and +7.6% sheared, outside
// the bounds; redistribution moves less than 0.6% on this mild relief, so for it the bounds only
// catch gross errors.
TEST(Metric, AnisotropicAndShearedUvAgreeWithDisplacement) {
  const Vec2 aniso[4] = {{0, 0}, {40.0f / 3.0f, 0}, {40.0f / 3.0f, 40}, {0, 40}};
  const Vec2 shear[4] = {{0, 0}, {40, 0}, {80, 40}, {40, 40}};
  const struct {
    const Vec2* uv;
    const char* name;
    double tolerance;
  } cases[] = {{aniso, "stretched", 0.013}, {shear, "sheared", 0.045}};
  for (const auto& c : cases) {
    const std::vector<double> reference =
        bandMeans(metricScene("displacement", "aniso", c.uv, 2.0f, 0.03f), 3);
    ASSERT_GE(reference.size(), 2u);
    for (const char* algorithm : {"brdf", "redistribution", "auto"}) {
      const std::vector<double> m =
          bandMeans(metricScene(algorithm, "aniso", c.uv, 2.0f, 0.03f), 3);
      ASSERT_EQ(m.size(), reference.size());
      for (size_t b = 0; b < m.size(); ++b)
        EXPECT_NEAR(m[b] / reference[b], 1.0, c.tolerance)
            << algorithm << " " << c.name << " band " << b << ": " << m[b] << " against "
            << reference[b];
    }
  }
}

// Strongly sheared or stretched metric classes get twice the view-azimuth slices (their visible
// normals change fast with phi_V); an isotropic orthogonal uv keeps render.tables.phi_v_bins, and
// so does a mild stretch.
TEST(Metric, ShearedAndStretchedClassesGetTwiceTheViewSlices) {
  const Vec2 unit[4] = {{0, 0}, {40, 0}, {40, 40}, {0, 40}};
  const Vec2 mild[4] = {{0, 0}, {40.0f / 1.4f, 0}, {40.0f / 1.4f, 40}, {0, 40}};   // log2 a = 0.24
  const Vec2 aniso[4] = {{0, 0}, {40.0f / 3.0f, 0}, {40.0f / 3.0f, 40}, {0, 40}};  // 0.79
  const Vec2 shear[4] = {{0, 0}, {40, 0}, {80, 40}, {40, 40}};                     // b = -1
  const struct {
    const Vec2* uv;
    int factor;
  } cases[] = {{unit, 1}, {mild, 1}, {aniso, 2}, {shear, 2}};
  for (const auto& c : cases) {
    Scene s = metricScene("brdf", "slices", c.uv, 2.0f, 0.03f);
    s.render.tables.phiVBins = 4;
    s.render.tables.azimuths = 8;
    PrepareTimes times;
    const RenderContext ctx = prepareRenderContext(s, times, {.buildFrame = false});
    ASSERT_EQ(ctx.reliefs[0].metrics.size(), 1u);
    const HistogramResolution& q = ctx.reliefs[0].metrics[0].levels[0].distr.resolution();
    EXPECT_EQ(q.phiV, 4 * c.factor) << "shape a " << ctx.reliefs[0].metrics[0].shape.a << " b "
                                    << ctx.reliefs[0].metrics[0].shape.b;
  }
}

// Relief too steep to tabulate (an amplitude of 1e6 once took 467 s of table building): the class
// is raised to the length at which the relief's rms slope is kMaxTableSlope, so twice the
// amplitude gives twice that length, with a warning; a sane amplitude keeps the plane's length.
TEST(Metric, ReliefSteeperThanTheTableCapIsTabulatedAtTheCap) {
  const Vec2 unit[4] = {{0, 0}, {40, 0}, {40, 40}, {0, 40}};
  std::vector<float> lengths;
  for (float amplitude : {0.03f, 1e6f, 2e6f}) {
    // Bump builds no tables but lists the classes, as the table renderers would get them.
    const Scene s = metricScene("bump", "steep", unit, 2.0f, amplitude);
    PrepareTimes times;
    const RenderContext ctx = prepareRenderContext(s, times, {.buildFrame = false});
    ASSERT_EQ(ctx.reliefs[0].metrics.size(), 1u);
    lengths.push_back(ctx.reliefs[0].metrics[0].lengthPerU);
    const bool steep = amplitude > 1.0f;
    bool warned = false;
    for (const std::string& w : ctx.warnings.list())
      warned = warned || (w.find("at most 100 is tabulated") != std::string::npos &&
                          w.find("world units per unit of u") != std::string::npos);
    EXPECT_EQ(warned, steep) << amplitude;
  }
  EXPECT_NEAR(lengths[0], 1.0f, 1e-4f);
  EXPECT_GT(lengths[1], 1e3f) << "an rms slope of about 1e6 per unit length, over 100";
  EXPECT_NEAR(lengths[2] / lengths[1], 2.0f, 1e-4f);
}

// A mesh so far from the origin that 32-bit positions are spaced more than 0.1% of its size apart
// is warned about, naming its file; at 1e3 units (spacing 6e-5) it is not.
TEST(Metric, AMeshFarFromTheOriginIsWarnedAbout) {
  const Vec2 unit[4] = {{0, 0}, {40, 0}, {40, 40}, {0, 40}};
  for (float offset : {1e3f, 1e7f}) {
    Scene s = metricScene("bump", "far", unit, 2.0f, 0.03f);
    s.objects[0].transform = glm::translate(Mat4(1.0f), Vec3(offset, 0.0f, 0.0f));
    PrepareTimes times;
    const RenderContext ctx = prepareRenderContext(s, times, {.buildFrame = false});
    bool warned = false;
    const std::string expected =
        s.objects[0].mesh.string() +
        ": it lies 1e+07 units from the origin, where positions (32-bit floats) are 1.1921 "
        "apart, 2.98% of its size (40)";
    for (const std::string& w : ctx.warnings.list())
      warned = warned || w.find(expected) != std::string::npos;
    EXPECT_EQ(warned, offset > 1e6f) << offset;
  }
}

// A plane whose u runs 10 times faster than v, its BRDF tables at the default 0.25-octave step and
// at a 0.01-octave one: the same image (the same tables), as both have the plane's own shape. With
// the quantized shapes (6% off in a at 0.25 octave) the bands differed by 1.1% and 0.6%.
TEST(Metric, StretchedPlaneTablesDoNotDependOnTheShapeStep) {
  const Vec2 stretched[4] = {{0, 0}, {4, 0}, {4, 40}, {0, 40}};
  std::vector<std::vector<double>> means;
  for (float step : {0.25f, 0.01f}) {
    Scene s = metricScene("brdf", "step", stretched, 2.0f, 0.06f);
    s.render.tables.metricStep = step;
    means.push_back(bandMeans(s, 3));
  }
  ASSERT_GE(means[0].size(), 2u);
  for (size_t b = 0; b < means[0].size(); ++b)
    EXPECT_NEAR(means[1][b] / means[0][b], 1.0, 1e-6) << "band " << b;
}

// The tile map's length: the frame's own between the two classes' (in either order), the nearer
// class's outside them, the frame's own where the classes give nothing usable.
TEST(Metric, TableLengthIsTheFramesOwnClampedToTheClasses) {
  EXPECT_EQ(tableLengthPerU(1.3f, 1.0f, 2.0f), 1.3f);
  EXPECT_EQ(tableLengthPerU(1.3f, 2.0f, 1.0f), 1.3f);
  EXPECT_EQ(tableLengthPerU(1.118f, 1.0f, 1.0f), 1.0f);  // a finer level stretched by a slope
  EXPECT_EQ(tableLengthPerU(0.5f, 1.0f, 2.0f), 1.0f);
  EXPECT_EQ(tableLengthPerU(3.0f, 1.0f, 2.0f), 2.0f);
  EXPECT_EQ(tableLengthPerU(1.5f, 0.0f, 0.0f), 1.5f);
  EXPECT_TRUE(std::isnan(tableLengthPerU(std::nanf(""), 1.0f, 2.0f)));
}

// TileMap: M^-1 (M t) = t, and M^-T n is normal to every M t with t normal to n.
// Where a point's metric falls between a material's classes (sorted by length, identity shape):
// known positions, w in log length; the (P_u, P_v) form is the same, and with one class or none it
// is class 0 whatever the point's metric, as measuring it would give.
TEST(Metric, PositionBetweenClassesInLogLength) {
  MaterialRelief relief;
  for (float l : {1.0f, 2.0f, 4.0f}) relief.metrics.push_back(MetricTables{l, {}, {}});
  const auto square = [](float l) { return std::pair(Vec3(l, 0, 0), Vec3(0, l, 0)); };
  const struct {
    float l;
    int k0, k1;
    float w;
  } cases[] = {{0.5f, 0, 0, 0.0f},
               {1.0f, 0, 0, 0.0f},
               {std::sqrt(2.0f), 0, 1, 0.5f},
               {2.0f, 1, 2, 0.0f},
               {3.0f, 1, 2, std::log2(1.5f)},
               {4.0f, 2, 2, 0.0f},
               {8.0f, 2, 2, 0.0f}};
  for (const auto& c : cases) {
    const auto [Pu, Pv] = square(c.l);
    const MetricPosition p = relief.metricAt(Pu, Pv);
    EXPECT_EQ(p.k0, c.k0) << c.l;
    EXPECT_EQ(p.k1, c.k1) << c.l;
    EXPECT_NEAR(p.w, c.w, 1e-5f) << c.l;
    const MetricPosition q = relief.metricAt(metricOf(Pu, Pv));
    EXPECT_EQ(p.k0, q.k0);
    EXPECT_EQ(p.k1, q.k1);
    EXPECT_EQ(p.w, q.w);
  }
  for (size_t classes : {size_t{1}, size_t{0}}) {
    relief.metrics.resize(classes);
    const auto [Pu, Pv] = square(8.0f);
    const MetricPosition p = relief.metricAt(Pu, Pv);
    EXPECT_EQ(p.k0, 0);
    EXPECT_EQ(p.k1, 0);
    EXPECT_EQ(p.w, 0.0f);
    EXPECT_EQ(p.k0, relief.metricAt(metricOf(Pu, Pv)).k0);
  }
}

TEST(Metric, TileMapInvertsAndMapsNormals) {
  Rng rng(5);
  for (int k = 0; k < 1000; ++k) {
    const Vec3 Pu(1.0f + 3.0f * rng.uniform(), rng.uniform() - 0.5f, 0.0f);
    const Vec3 Pv(rng.uniform() - 0.5f, 0.3f + 2.0f * rng.uniform(), 0.0f);
    const Vec3 N = glm::normalize(glm::cross(Pu, Pv));
    const TileMap m = makeTileMap(Pu, Pv, N, 0.5f + rng.uniform());
    const Vec3 t(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f);
    const Vec3 w = t.x * m.a + t.y * m.b + t.z * m.N;
    const Vec3 back = m.toTile(w);
    EXPECT_LT(glm::length(back - t), 1e-4f);
    const Vec3 n = glm::normalize(Vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, 1.0f));
    const Vec3 tangent = glm::cross(n, Vec3(rng.uniform(), rng.uniform(), rng.uniform()));
    const Vec3 mt = tangent.x * m.a + tangent.y * m.b + tangent.z * m.N;
    EXPECT_LT(std::abs(glm::dot(m.normalToWorld(n), mt)),
              1e-4f * glm::length(mt) * glm::length(m.normalToWorld(n)));
  }
}

// Geometry and shading take disp per level from one evaluation: on a two-level relief, the disp
// the shader assumes equals the tessellator's at 1e4 random points.
TEST(Metric, GeometryAndShadingAgreeOnDispPerLevel) {
  const Vec2 uv[4] = {{0, 0}, {40, 0}, {40, 40}, {0, 40}};
  Scene s = metricScene("auto", "levels", uv, 0.5f, 0.05f);
  ReliefLevelDecl fine = testing::noiseLevel(0.004f, 6.0f, 2);
  fine.seed = 9;
  s.materials[0].relief.push_back(fine);
  s.camera.position = {0.0f, -3.0f, 1.0f};
  s.camera.width = 320;
  s.camera.height = 180;
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(s, times);
  const PreparedObject& object = ctx.objects[0];
  ASSERT_TRUE(object.displaced);
  // With shadows (the default) the lights' terminators count in T, for the tessellator as for the
  // shader.
  ASSERT_TRUE(ctx.shadows);
  const ReliefDisplacement geometry(ctx.reliefs[0], DisplacementMode::ByTransition,
                                    s.render.transition, ctx.camera.position(),
                                    ctx.camera.pixelsPerRadian(), s.lights);
  Rng rng(12);
  int partial = 0;
  for (int k = 0; k < 10000; ++k) {
    const SurfacePoint sp = object.surface.evaluate(0, Vec2(rng.uniform(), rng.uniform()));
    const LevelDisplacement d = geometry.levels(sp);
    const ShadeResult r =
        shadeSurface(ctx, object, sp, glm::normalize(ctx.camera.position() - sp.P), s.lights,
                     nullptr, nullptr, &sp.P);
    for (int i = 0; i < 2; ++i) {
      EXPECT_NEAR(r.disp[i], d.disp[i], 1e-6f) << "level " << i;
      partial += d.disp[i] > 0.0f && d.disp[i] < 1.0f;
    }
  }
  EXPECT_GT(partial, 50) << "the camera should see partly displaced relief";
}

// Heights are centred: the default midlevel is the source's mean, so the displaced plane's mean
// height is 0 (the plane the smooth renderers draw).
TEST(Metric, DefaultMidlevelIsTheMean) {
  const ReliefLevel level = makeReliefLevel(testing::noiseLevel(0.1f, 3.0f, 3));
  double sum = 0.0;
  constexpr int kGrid = 256;
  for (int j = 0; j < kGrid; ++j)
    for (int i = 0; i < kGrid; ++i)
      sum += level.height(Vec2((i + 0.5f) / kGrid, (j + 0.5f) / kGrid) / 3.0f);
  EXPECT_NEAR(sum / (kGrid * kGrid), 0.0, 1e-3 * 0.1);
  EXPECT_NE(level.midlevel, 0.0f);
  ReliefLevelDecl explicitMid = testing::noiseLevel(0.1f, 3.0f, 3);
  explicitMid.midlevel = 0.5f;
  EXPECT_EQ(makeReliefLevel(explicitMid).midlevel, 0.5f);
}

}  // namespace
}  // namespace meso
