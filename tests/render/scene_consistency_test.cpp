// meso consistency SCENE: each renderer against the displacement reference, per object and band.
#include "meso/render/scene_consistency.h"

#include "meso/render/local_contrast.h"
#include "support/plane_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace meso {
namespace {

Scene smallScene() {
  Material m;
  m.kd = Vec3(0.7f);
  m.relief = {testing::noiseLevel(0.01f, 2.0f, 2)};
  Scene s = testing::planeScene(testing::writePlaneObj("scons", 10.0f, 0.0f, 20.0f), "auto", m,
                                Vec3(0.3f, 0.5f, -0.8f), "scons");
  s.camera.position = {0.0f, -9.0f, 2.0f};
  s.camera.lookAt = {0.0f, 0.0f, 0.0f};
  s.camera.width = 48;
  s.camera.height = 27;
  s.camera.fovY = 40.0f;
  s.camera.spp = 1;
  s.render.tables.raysPerView = 256;
  s.render.tables.phiVBins = 4;
  return s;
}

// The displacement renderer at the reference's own dicing is the reference: zero difference in
// every region; regions partition the pixels that hit; the coarse reference differs a little.
TEST(SceneConsistency, ReferenceAgainstItselfAndRegions) {
  Scene s = smallScene();
  s.render.dicingRate = 0.5f;
  // Dicing by pixels only: the reference doubles relief_samples, and twice 0 is 0.
  s.render.reliefSamples = 0.0f;
  SceneConsistencyOptions o;
  o.algorithms = {Algorithm::Displacement, Algorithm::Bump};
  o.bands = 3;
  o.referenceDicing = 0.5f;
  const SceneConsistencyReport r = sceneConsistency(s, o);
  ASSERT_EQ(r.renderers.size(), 4u);
  EXPECT_EQ(r.renderers[0], "reference");
  ASSERT_EQ(r.regions.size(), 4u);  // one object, three bands
  int64_t bandPixels = 0;
  for (size_t k = 1; k < r.regions.size(); ++k) bandPixels += r.regions[k].pixels;
  EXPECT_EQ(bandPixels, r.regions[0].pixels);
  EXPECT_GT(r.regions[0].pixels, 48 * 27 / 3);
  for (const ConsistencyRegion& region : r.regions) {
    if (region.pixels == 0) continue;
    EXPECT_EQ(region.mean[2], region.mean[0])
        << region.name;  // displacement at the reference's dicing
    EXPECT_GT(region.mean[0], 0.0);
    for (double m : region.mean) EXPECT_TRUE(std::isfinite(m));
  }
  EXPECT_GT(r.referenceChange, 0.0);
  EXPECT_LT(r.referenceChange, 0.05);
  EXPECT_FALSE(r.referenceCoarsened);
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_EQ(r.worstRenderer, "bump");  // displacement is exact, so bump is the worst
  const std::string csv = formatSceneConsistency(r, TableFormat::Csv),
                    md = formatSceneConsistency(r, TableFormat::Markdown);
  EXPECT_NE(csv.find("region,pixels,reference,coarse reference,displacement,bump"),
            std::string::npos)
      << csv;
  EXPECT_NE(md.find("| region | pixels | reference"), std::string::npos) << md;
}

// A light 10 degrees below the plane, without shadows: displacement lights the facets that face it,
// and so do the BRDF tables, which go on past theta_L = 90 degrees. They stopped there, and the
// BRDF drew the plane with the ambient term only.
TEST(SceneConsistency, BrdfLightsFacetsThatFaceALightBelowThePlane) {
  Scene s = smallScene();
  s.materials[0].relief = {testing::noiseLevel(0.08f, 2.0f, 2)};
  s.materials[0].ka = Vec3(0.03f);
  s.lights[0].direction = glm::normalize(Vec3(0.0f, 0.985f, 0.174f));  // travelling up
  s.render.shadows = false;
  SceneConsistencyOptions o;
  o.algorithms = {Algorithm::Brdf, Algorithm::Redistribution};
  o.bands = 1;
  o.referenceDicing = 0.5f;
  const SceneConsistencyReport r = sceneConsistency(s, o);
  ASSERT_FALSE(r.regions.empty());
  const ConsistencyRegion& plane = r.regions[0];
  const double reference = plane.mean[0], brdf = plane.mean[2], redistribution = plane.mean[3];
  std::printf(
      "[ figure ] light 10 degrees below the plane: reference %.4f, brdf %.4f, "
      "redistribution %.4f, ambient 0.03\n",
      reference, brdf, redistribution);
  EXPECT_GT(reference, 0.06) << "the displaced facets that face the light are lit";
  EXPECT_NEAR(brdf / reference, 1.0, 0.03);
  EXPECT_NEAR(redistribution / reference, 1.0, 0.05);
}

// A reference that the micropolygon cap coarsened is not diced as asked, and says so: its change
// over one halving of dicing would measure nothing.
TEST(SceneConsistency, CoarsenedReferenceIsFlagged) {
  Scene s = smallScene();
  s.render.maxMicropolygons = 1000;
  SceneConsistencyOptions o;
  o.algorithms = {Algorithm::Bump};
  o.bands = 1;
  o.referenceDicing = 0.5f;
  const SceneConsistencyReport r = sceneConsistency(s, o);
  EXPECT_TRUE(r.referenceCoarsened);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].find("would exceed the cap of 1000"), std::string::npos) << r.warnings[0];
  // Coarsened farthest first: where it began, and how far each region reaches.
  EXPECT_TRUE(std::isfinite(r.referenceAsAskedWithin));
  for (const ConsistencyRegion& region : r.regions)
    EXPECT_TRUE(region.pixels == 0 || region.farthest > 0.0) << region.name;
}

// Relief of a few pixels per wavelength seen from above under a low light: the BRDF keeps each
// region's mean but draws no texture and fails the detail check; displacement diced by pixels
// (1 px) keeps the reference's local contrast and passes.
// `level` on the small plane under a low light, seen from `eye` at 96 x 64, 4 spp: each renderer
// of `algorithm` and the BRDF against the reference at 0.25 px, in two depth bands; prints each
// region's figures.
SceneConsistencyReport reliefUnderALowLight(const ReliefLevelDecl& level, const Vec3& eye,
                                            Algorithm algorithm, float dicingRate) {
  Scene s = smallScene();
  s.materials[0].relief = {level};
  s.lights[0].direction = glm::normalize(Vec3(0.8f, 0.3f, -0.5f));
  s.camera.position = eye;
  s.camera.width = 96;
  s.camera.height = 64;
  s.camera.spp = 4;
  s.render.dicingRate = dicingRate;
  SceneConsistencyOptions o;
  o.algorithms = {algorithm, Algorithm::Brdf};
  o.bands = 2;
  o.referenceDicing = 0.25f;
  const SceneConsistencyReport r = sceneConsistency(s, o);
  for (const ConsistencyRegion& region : r.regions)
    std::printf(
        "[ figure ] %s: reference contrast %.4f; %s mean %+.2f%%, contrast ratio %.3f; "
        "brdf mean %+.2f%%, contrast ratio %.3f\n",
        region.name.c_str(), region.contrast[0], r.renderers[2].c_str(),
        100.0 * (region.mean[2] / region.mean[0] - 1.0), region.contrastRatio[2],
        100.0 * (region.mean[3] / region.mean[0] - 1.0), region.contrastRatio[3]);
  return r;
}

TEST(SceneConsistency, BrdfOfVisibleReliefFailsTheDetailCheck) {
  const SceneConsistencyReport r = reliefUnderALowLight(
      testing::noiseLevel(0.06f, 0.5f, 2), {0.0f, -5.0f, 6.0f}, Algorithm::Displacement, 1.0f);
  ASSERT_EQ(r.regions.size(), 3u);
  for (const ConsistencyRegion& region : r.regions) {
    EXPECT_GT(region.contrast[0], 5.0 * kReliefContrastFloor) << region.name;
    EXPECT_NEAR(region.mean[3] / region.mean[0], 1.0, 0.02) << region.name;  // the mean is kept
    EXPECT_FALSE(asDetailed(region.contrastRatio[3])) << region.name;
    EXPECT_LT(region.contrastRatio[3], 0.5) << region.name;
    EXPECT_TRUE(asDetailed(region.contrastRatio[2])) << region.name;
    EXPECT_TRUE(asDetailed(region.contrastRatio[1])) << region.name;  // the coarse reference
  }
  EXPECT_EQ(r.notDetailed, std::vector<std::string>{"brdf"});
  EXPECT_EQ(r.worstContrastRenderer, "brdf");
  EXPECT_LT(r.referenceContrastChange, kContrastTolerance);
  const std::string csv = formatSceneConsistency(r, TableFormat::Csv);
  EXPECT_NE(csv.find(",reference contrast,coarse reference contrast ratio,displacement contrast "
                     "ratio,brdf contrast ratio\n"),
            std::string::npos)
      << csv;
}

// Three octaves whose shortest wavelength spans about a pixel and whose longest several, under a
// low light: the hybrid redistributes them (T = 0 between the two) and keeps the reference's local
// contrast and mean, where the BRDF table, which T of the shortest wavelength alone would pick
// (nu < D), keeps the mean and draws no texture.
TEST(SceneConsistency, AutoKeepsTheContrastOfOctavesThatSpanPixels) {
  const SceneConsistencyReport r = reliefUnderALowLight(testing::noiseLevel(0.06f, 0.5f, 3),
                                                        {0.0f, -6.0f, 7.0f}, Algorithm::Auto, 1.0f);
  ASSERT_EQ(r.regions.size(), 3u);
  for (const ConsistencyRegion& region : r.regions) {
    EXPECT_GT(region.contrast[0], 5.0 * kReliefContrastFloor) << region.name;
    EXPECT_NEAR(region.mean[2] / region.mean[0], 1.0, 0.01) << region.name;
    EXPECT_TRUE(asDetailed(region.contrastRatio[2])) << region.name;
    EXPECT_LT(region.contrastRatio[3], 0.5) << region.name;
  }
  EXPECT_EQ(r.notDetailed, std::vector<std::string>{"brdf"});
}

}  // namespace
}  // namespace meso
