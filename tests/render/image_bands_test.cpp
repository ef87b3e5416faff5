// A height image split into band-limited levels (scene/relief_bands.h): each level's tables are
// of its band and every finer band summed (ReliefLevel::partialSum), so where no band is raised
// the image is drawn exactly as one level.
#include "meso/appearance/material_tables.h"
#include "meso/core/image_io.h"
#include "meso/render/scene_consistency.h"
#include "meso/render/transition.h"
#include "meso/scene/relief_bands.h"
#include "support/offsets_agree.h"
#include "support/plane_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <unistd.h>

namespace meso {
namespace {

// A 64 x 64 height EXR of two independent scales: a wave along x at 3 cycles and one along y at
// 11 cycles of about equal slope, each inside one octave band (crossovers at 2, 4, 8 and 16
// cycles); their slope magnitudes do not correlate, so the split is made.
std::filesystem::path twoScaleImage() {
  const std::filesystem::path file =
      testing::ProcessTemporaries::add(std::filesystem::temp_directory_path() /
                                       ("meso_image_bands_" + std::to_string(::getpid()) + ".exr"));
  Image img(64, 64, {"Y"});
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      img.at(x, y, 0) = 0.5f + 0.3f * std::sin(2 * kPi * 3 * (x + 0.5f) / 64) +
                        0.08f * std::sin(2 * kPi * 11 * (y + 0.5f) / 64);
  writeExr(file, img);
  return file;
}

ReliefLevelDecl imageLevel(const std::filesystem::path& file, int bands) {
  ReliefLevelDecl d;
  d.source = ReliefSource::Image;
  d.height = file;
  d.amplitude = 0.05f;
  d.scale = 2.0f;
  d.bands = bands;
  return d;
}

Scene planeWith(std::vector<ReliefLevelDecl> relief, const std::string& tag) {
  Material m;
  m.kd = Vec3(0.7f);
  m.relief = std::move(relief);
  Scene s = testing::planeScene(testing::writePlaneObj(tag, 10.0f, 0.0f, 20.0f), "auto", m,
                                Vec3(0.3f, 0.5f, -0.8f), tag);
  s.camera.position = {0.0f, -9.0f, 3.0f};
  s.camera.lookAt = {0.0f, 0.0f, 0.0f};
  s.camera.width = 32;
  s.camera.height = 18;
  s.camera.fovY = 40.0f;
  s.camera.spp = 1;
  s.render.tables.raysPerView = 256;
  s.render.tables.phiVBins = 4;
  s.render.shadows = false;
  return s;
}

// Two levels; the coarse one's partial sum is the whole image and covers both levels; the finest
// has none.
TEST(ImageBands, CoarseLevelsTabulateTheSumOfTheirImagesFinerBands) {
  const std::vector<ReliefLevelDecl> decls = expandImageBands(imageLevel(twoScaleImage(), 0), 8);
  ASSERT_EQ(decls.size(), 2u);
  std::vector<ReliefLevel> levels;
  for (const ReliefLevelDecl& d : decls) levels.push_back(makeReliefLevel(d));
  linkImageBands(decls, levels);
  ASSERT_TRUE(levels[0].partialSum);
  EXPECT_EQ(levels[0].partialSumEnd, 2u);
  EXPECT_FALSE(levels[1].partialSum);
  EXPECT_GT(levels[1].freqPerU, 1.5f * levels[0].freqPerU);
  // The sum's heights are the two levels' (each about its own mean), and the image's.
  const ReliefLevel whole = makeReliefLevel(imageLevel(twoScaleImage(), 1));
  for (const Vec2 uv : {Vec2(0.1f, 0.2f), Vec2(0.37f, 0.81f), Vec2(0.77f, 0.05f)}) {
    EXPECT_NEAR(levels[0].partialSum->height(uv), levels[0].height(uv) + levels[1].height(uv),
                1e-5f);
    EXPECT_NEAR(levels[0].partialSum->height(uv), whole.height(uv), 1e-5f);
  }
}

// A band raised in part rises by disp times its partial sum (the sum its tables remap through
// theta_W), its finer bands flat; raised whole, by its own band, the next band raised on it.
TEST(ImageBands, ABandRaisedInPartRaisesItsPartialSum) {
  const std::vector<ReliefLevelDecl> decls = expandImageBands(imageLevel(twoScaleImage(), 0), 8);
  ASSERT_EQ(decls.size(), 2u);
  MaterialRelief relief;
  for (const ReliefLevelDecl& d : decls) relief.levels.push_back(makeReliefLevel(d));
  linkImageBands(decls, relief.levels);
  ASSERT_TRUE(relief.levels[0].partialSum);
  const SurfacePoint sp{Vec3(0.0f), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec2(0.3f, 0.4f)};
  const TransitionSettings ts;
  int partly = 0, whole = 0;
  for (float distance = 0.5f; distance < 5000.0f; distance *= 1.1f) {
    const Vec3 eye(0.0f, 0.6f * distance, 0.8f * distance);
    const LevelTransitions t =
        levelTransitions(relief, sp, eye, 500.0f, ts, DisplacementMode::ByTransition);
    testing::expectOffsetsAgree(
        levelTransitions(relief, sp, ReliefCoord{sp.uv}, eye, 500.0f, ts,
                         DisplacementMode::ByTransition, {}, TransitionsFor::Offsets),
        t, "distance " + std::to_string(distance));
    if (!(t.disp[0] > 0.0f)) continue;
    const bool part = t.disp[0] < 1.0f;
    const ReliefLevel& raisedAs = part ? *relief.levels[0].partialSum : relief.levels[0];
    Vec2 B;
    const float H = raisedAs.heightAndDerivatives(sp.uv, B);
    EXPECT_EQ(t.H[0], H) << distance;
    EXPECT_EQ(t.B[0], B) << distance;
    if (part) {
      EXPECT_EQ(t.disp[1], 0.0f) << distance;  // the finer band is in the sum, not raised
      EXPECT_EQ(t.raised, 1);
      ++partly;
    } else {
      ++whole;
    }
  }
  EXPECT_GT(partly, 0);
  EXPECT_GT(whole, 0);
  // The two differ here: the sum carries the finer band's height.
  EXPECT_GT(std::abs(relief.levels[0].partialSum->height(sp.uv) - relief.levels[0].height(sp.uv)),
            1e-4f);
}

// The BRDF and redistribution renderers draw the banded image as the one-level image (its first
// level's tables are of the whole image); bump, which sums the bands' Blinn normals, too.
TEST(ImageBands, FarRenderersDrawTheBandedImageAsOneLevel) {
  const std::filesystem::path file = twoScaleImage();
  const std::vector<ReliefLevelDecl> banded = expandImageBands(imageLevel(file, 0), 8);
  ASSERT_EQ(banded.size(), 2u);
  SceneConsistencyOptions o;
  o.algorithms = {Algorithm::Brdf, Algorithm::Redistribution, Algorithm::Bump};
  o.bands = 1;
  o.referenceDicing = 1.0f;
  const SceneConsistencyReport a = sceneConsistency(planeWith(banded, "bands2"), o);
  const SceneConsistencyReport b = sceneConsistency(planeWith({imageLevel(file, 1)}, "bands1"), o);
  ASSERT_EQ(a.regions.size(), b.regions.size());
  for (size_t k = 2; k <= 4; ++k) {  // the reference and the coarse reference come first
    EXPECT_NEAR(a.regions[0].mean[k], b.regions[0].mean[k], 1e-3 * b.regions[0].mean[k])
        << a.renderers[k];
    EXPECT_TRUE(std::isfinite(a.regions[0].mean[k]));
  }
}

}  // namespace
}  // namespace meso
