// The scene reader: a complete scene, defaults, the transform order, and one test per class of bad
// input, each checking FILE:LINE:COL: key: in the message.
#include "meso/core/error.h"
#include "meso/core/image_io.h"
#include "meso/core/math.h"
#include "meso/scene/scene_parser.h"

#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace meso {
namespace {

namespace fs = std::filesystem;

class SceneReaderTest : public testing::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    write("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
    // One wave: its octave bands are one level (the reader reads height images to split them).
    Image bumps(32, 32, {"R", "G", "B"});
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x)
        for (int c = 0; c < 3; ++c)
          bumps.at(x, y, c) = 0.5f + 0.3f * std::sin(2.0f * kPi * 4.0f * (x + 0.5f) / 32.0f);
    writeExr(dir_ / "bumps.exr", bumps);
  }

  Scene parse(const std::string& text) { return parseScene(text, dir_ / "scene.toml"); }
  // The message of the Error that parsing `text` throws.
  std::string errorOf(const std::string& text) {
    try {
      parse(text);
    } catch (const Error& e) {
      return e.what();
    }
    ADD_FAILURE() << "no error for:\n" << text;
    return "";
  }
  std::string at(int line, int col, const std::string& key) {
    return (dir_ / "scene.toml").string() + ":" + std::to_string(line) + ":" + std::to_string(col) +
           ": " + key + ": ";
  }
};

constexpr const char* kObject = "[[objects]]\nmesh = \"quad.obj\"\n";

TEST_F(SceneReaderTest, CompleteSceneParsesEveryValue) {
  const Scene s = parse(R"(
[camera]
position = [1, 2, 3]
look_at = [0, 0.5, 0]
up = [0, 0, 1]
fov = 30.5
resolution = [320, 200]
spp = 9

[[lights]]
type = "point"
position = [0, 5, 0]
intensity = 7
colour = [1, 0.5, 0.25]

[[lights]]
direction = [0, 0, -2]

[[materials]]
name = "a"
ka = 0.1
kd = [0.2, 0.3, 0.4]
ks = 0.5
phong = 64
  [[materials.relief]]
  height = "bumps.exr"
  amplitude = 0.02
  scale = 4
  [[materials.relief]]
  noise = { octaves = 3, lacunarity = 2.5, gain = 0.4, seed = 9, periodic = false }
  amplitude = 0.001
  freq = 64

[[materials]]
name = "b"

[[objects]]
mesh = "quad.obj"
scheme = "bilinear"
material = "b"
translate = [1, 0, 0]
scale = 2

[render]
algorithm = "bump"
seed = 42
threads = 2
tessellation_rate = 5
background = [0.1, 0.2, 0.3]
D = 3
eps = 0.2
thresholds = [-2, -0.5, 0.5, 2]
dicing_rate = 0.5
dicing_metric = "projected"
across_view_cap = 0.75
normals = "facet"
)");
  EXPECT_EQ(s.camera.position, Vec3(1, 2, 3));
  EXPECT_EQ(s.camera.up, Vec3(0, 0, 1));
  EXPECT_FLOAT_EQ(s.camera.fovY, 30.5f);
  EXPECT_EQ(s.camera.width, 320);
  EXPECT_EQ(s.camera.height, 200);
  EXPECT_EQ(s.camera.spp, 9);
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.lights[0].type, LightType::Point);
  EXPECT_EQ(s.lights[0].colour, Vec3(1, 0.5f, 0.25f));
  EXPECT_EQ(s.lights[1].type, LightType::Directional);
  EXPECT_EQ(s.lights[1].direction, Vec3(0, 0, -1));  // normalized
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[0].ka, Vec3(0.1f));
  EXPECT_EQ(s.materials[0].kd, Vec3(0.2f, 0.3f, 0.4f));
  EXPECT_FLOAT_EQ(s.materials[0].phong, 64.0f);
  ASSERT_EQ(s.materials[0].relief.size(), 2u);
  EXPECT_EQ(s.materials[0].relief[0].source, ReliefSource::Image);
  EXPECT_EQ(s.materials[0].relief[0].height, dir_ / "bumps.exr");
  EXPECT_FLOAT_EQ(s.materials[0].relief[0].scale, 4.0f);
  EXPECT_EQ(s.materials[0].relief[1].source, ReliefSource::Noise);
  EXPECT_EQ(s.materials[0].relief[1].octaves, 3);
  EXPECT_EQ(s.materials[0].relief[1].seed, 9u);
  EXPECT_FALSE(s.materials[0].relief[1].periodic);
  EXPECT_FLOAT_EQ(s.materials[0].relief[1].freq, 64.0f);
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_EQ(s.objects[0].mesh, dir_ / "quad.obj");
  EXPECT_EQ(s.objects[0].scheme, SubdivisionScheme::Bilinear);
  EXPECT_EQ(s.objects[0].material, 1);
  EXPECT_EQ(s.render.algorithm, Algorithm::Bump);
  EXPECT_EQ(s.render.seed, 42u);
  EXPECT_EQ(s.render.threads, 2);
  EXPECT_EQ(s.render.tessellationRate, 5);
  EXPECT_FLOAT_EQ(s.render.transition.D, 3.0f);
  EXPECT_FLOAT_EQ(s.render.transition.e4, 2.0f);
  EXPECT_FLOAT_EQ(s.render.dicingRate, 0.5f);
  EXPECT_EQ(s.render.dicingMetric, DicingMetric::Projected);
  EXPECT_FLOAT_EQ(s.render.acrossViewCap, 0.75f);
  EXPECT_EQ(s.render.normals, ShadingNormals::Facet);
}

TEST_F(SceneReaderTest, DefaultsAndTransformOrder) {
  const Scene s = parse(std::string(kObject) +
                        "translate = [10, 0, 0]\nrotate = [0, 0, 90]\nscale = [2, 1, 1]\n");
  EXPECT_EQ(s.camera.width, 640);
  EXPECT_EQ(s.camera.spp, 4);
  EXPECT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.render.algorithm, Algorithm::Auto);
  EXPECT_EQ(s.render.dicingMetric, DicingMetric::Isotropic);
  EXPECT_FLOAT_EQ(s.render.acrossViewCap, 0.5f);
  EXPECT_EQ(s.render.tessellationRate, 0);  // by view
  // T * Rz * Ry * Rx * S: (1, 0, 0) -> scaled (2, 0, 0) -> rotated (0, 2, 0) -> translated (10, 2,
  // 0).
  const Vec4 p = s.objects[0].transform * Vec4(1, 0, 0, 1);
  EXPECT_NEAR(p.x, 10.0f, 1e-5f);
  EXPECT_NEAR(p.y, 2.0f, 1e-5f);
  EXPECT_NEAR(p.z, 0.0f, 1e-5f);
}

TEST_F(SceneReaderTest, UnknownKeysAreRejectedAtEveryLevel) {
  EXPECT_NE(errorOf(std::string(kObject) + "colour = 1\n")
                .find(at(3, 1, "objects.colour") + "unknown key"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string("[camera]\nfocal = 3\n") + kObject).find(at(2, 1, "camera.focal")),
            std::string::npos);
  EXPECT_NE(errorOf(std::string("lamps = 1\n") + kObject)
                .find(at(1, 1, "lamps") + "unknown key (allowed here:"),
            std::string::npos);
  EXPECT_NE(
      errorOf(
          std::string(kObject) +
          "[[materials]]\nname = \"x\"\n[[materials.relief]]\nnoise = { octaves = 2, size = 3 }\n")
          .find("materials.relief.noise.size: unknown key"),
      std::string::npos);
}

TEST_F(SceneReaderTest, WrongTypesAreRejected) {
  EXPECT_NE(errorOf(std::string("[camera]\nfov = \"wide\"\n") + kObject)
                .find(at(2, 7, "camera.fov") + "expected a number, got a string"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string("[camera]\nspp = 2.5\n") + kObject)
                .find(at(2, 7, "camera.spp") + "expected an integer, got 2.5"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string("[camera]\nposition = [1, 2]\n") + kObject)
                .find(at(2, 12, "camera.position") + "expected an array of 3 numbers"),
            std::string::npos);
  EXPECT_NE(
      errorOf(std::string("camera = 3\n") + kObject).find(at(1, 10, "camera") + "expected a table"),
      std::string::npos);
}

TEST_F(SceneReaderTest, NanInfAndOutOfRangeAreRejected) {
  EXPECT_NE(errorOf(std::string("[camera]\nfov = nan\n") + kObject)
                .find(at(2, 7, "camera.fov") + "expected a finite number"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string("[[lights]]\nintensity = inf\n") + kObject)
                .find(at(2, 13, "lights.intensity") + "expected a finite number"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string("[camera]\nfov = 190\n") + kObject)
                .find(at(2, 7, "camera.fov") + "expected a number in (0, 180), got 190"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string("[camera]\nresolution = [0, 10]\n") + kObject)
                .find("camera.resolution: expected a number in [1, 16384]"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string("[render]\nspp = 1\n") + kObject).find("render.spp: unknown key"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string("[[materials]]\nname = \"m\"\nkd = [1, -1, 0]\n") + kObject)
                .find(at(3, 10, "materials.kd") + "expected a number in [0, 1e+06], got -1"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string("[render]\ntessellation_rate = 65\n") + kObject)
                .find("render.tessellation_rate: expected an integer in [0, 64], got 65"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kObject) + "scale = 0\n")
                .find(at(3, 9, "objects.scale") + "expected non-zero"),
            std::string::npos);
}

TEST_F(SceneReaderTest, EnumsReferencesAndDuplicatesAreChecked) {
  EXPECT_NE(errorOf(std::string(kObject) + "scheme = \"doo-sabin\"\n")
                .find(at(3, 10, "objects.scheme") +
                      "expected one of catmull-clark | loop | bilinear, got \"doo-sabin\""),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kObject) + "material = \"gold\"\n")
                .find(at(3, 12, "objects.material") + "no material named \"gold\""),
            std::string::npos);
  EXPECT_NE(
      errorOf("[[materials]]\nname = \"a\"\n[[materials]]\nname = \"a\"\n" + std::string(kObject))
          .find(at(4, 8, "materials.name") + "duplicate material name"),
      std::string::npos);
  EXPECT_NE(errorOf(std::string("[render]\nthresholds = [-1, 0.5, 0.3, 1]\n") + kObject)
                .find(at(2, 14, "render.thresholds") +
                      "expected [e1, e2, e3, e4] with e1 < e2 < 0 < e3 < e4"),
            std::string::npos);
  EXPECT_NE(
      errorOf(std::string("[render]\nacross_view_cap = 0\n") + kObject)
          .find(at(2, 19, "render.across_view_cap") + "expected a number in [0.05, 1], got 0"),
      std::string::npos);
}

// split_octaves: one level per octave of the noise, in order, each with its octave range; wrong
// uses are errors at their key.
TEST_F(SceneReaderTest, SplitOctavesMakesOneLevelPerOctave) {
  const std::string head = "[[materials]]\nname = \"m\"\n  [[materials.relief]]\n";
  const Scene s = parse(head +
                        "  noise = { octaves = 3, seed = 5 }\n  amplitude = 0.1\n"
                        "  split_octaves = true\n" +
                        kObject);
  ASSERT_EQ(s.materials[0].relief.size(), 3u);
  for (int o = 0; o < 3; ++o) {
    EXPECT_EQ(s.materials[0].relief[o].firstOctave, o);
    EXPECT_EQ(s.materials[0].relief[o].octaves, o + 1);
    EXPECT_EQ(s.materials[0].relief[o].seed, 5u);
    EXPECT_FLOAT_EQ(s.materials[0].relief[o].amplitude, 0.1f);
  }
  EXPECT_EQ(parse(head + "  noise = { octaves = 3 }\n" + kObject).materials[0].relief.size(), 1u);
  EXPECT_NE(errorOf(head + "  noise = { octaves = 3 }\n  midlevel = 0.5\n  split_octaves = true\n" +
                    kObject)
                .find("materials.relief.midlevel: split_octaves gives each octave its own mean"),
            std::string::npos);
  EXPECT_NE(errorOf(head + "  noise = { octaves = 9 }\n  split_octaves = true\n" + kObject)
                .find("counting each octave of split_octaves (got 9)"),
            std::string::npos);
  EXPECT_NE(errorOf(head + "  noise = { octaves = 2 }\n  split_octaves = 1\n" + kObject)
                .find("split_octaves"),
            std::string::npos);
}

// Solid relief: its keys, split_octaves, and the combinations refused at their key.
// Sphere lights: a point light's radius, refused when negative.
TEST_F(SceneReaderTest, PointLightRadius) {
  const std::string light = "[[lights]]\ntype = \"point\"\nposition = [0, 0, 3]\n";
  EXPECT_FLOAT_EQ(parse(light + "radius = 0.25\n" + kObject).lights[0].radius, 0.25f);
  EXPECT_FLOAT_EQ(parse(light + kObject).lights[0].radius, 0.0f);
  EXPECT_NE(errorOf(light + "radius = -1\n" + kObject).find("lights.radius"), std::string::npos);
}

// Environment lights: a map file (relative to the scene) or a uniform sky, with their keys; at
// most one per scene; light samples within what a sample shades with shadows.
TEST_F(SceneReaderTest, EnvironmentLight) {
  const std::string env = "[[lights]]\ntype = \"environment\"\n";
  const Scene sky = parse(env + "colour = [0.2, 0.3, 0.4]\nintensity = 2\n" + kObject);
  ASSERT_TRUE(sky.environment);
  EXPECT_TRUE(sky.lights.empty());
  EXPECT_TRUE(sky.environment->file.empty());
  EXPECT_EQ(sky.environment->colour, Vec3(0.2f, 0.3f, 0.4f));
  EXPECT_FLOAT_EQ(sky.environment->intensity, 2.0f);
  EXPECT_EQ(sky.render.lightSamples, 16);
  EXPECT_EQ(sky.environment->loc.line, 1);
  const Scene map = parse("[[lights]]\ndirection = [0, -1, 0]\n" + env +
                          "environment = \"bumps.exr\"\nrotation = 30\nup = [0, 0, 2]\n"
                          "colour_space = \"linear\"\n" +
                          kObject + "[render]\nlight_samples = 64\n");
  ASSERT_TRUE(map.environment);
  EXPECT_EQ(map.lights.size(), 1u);
  EXPECT_EQ(map.environment->file, dir_ / "bumps.exr");
  EXPECT_FLOAT_EQ(map.environment->rotation, 30.0f);
  EXPECT_EQ(map.environment->up, Vec3(0.0f, 0.0f, 1.0f));
  EXPECT_EQ(map.environment->space, ColourSpace::Linear);
  EXPECT_EQ(map.render.lightSamples, 64);
  EXPECT_NE(errorOf(env + "environment = \"none.exr\"\n" + kObject).find("file not found"),
            std::string::npos);
  EXPECT_NE(
      errorOf(env + "direction = [0, 0, 1]\n" + kObject).find("lights.direction: unknown key"),
      std::string::npos)
      << errorOf(env + "direction = [0, 0, 1]\n" + kObject);
  EXPECT_NE(errorOf(env + env + kObject)
                .find("scene.toml:3:1: lights.type: at most one environment light per scene (the "
                      "first is at line 1)"),
            std::string::npos)
      << errorOf(env + env + kObject);
  EXPECT_NE(errorOf(env + kObject + "[render]\nlight_samples = 65\n").find("render.light_samples"),
            std::string::npos);
  std::string many;
  for (int i = 0; i < 20; ++i) many += "[[lights]]\ndirection = [0, -1, 0]\n";
  EXPECT_NE(
      errorOf(many + env + kObject + "[render]\nlight_samples = 64\n")
          .find("render.light_samples: the environment's 64 light samples and 20 other lights "
                "make 84"),
      std::string::npos);
  EXPECT_FALSE(parse(many + kObject).environment);  // without one, any number of lights
}

TEST_F(SceneReaderTest, SolidReliefAndItsLimits) {
  const std::string head = "[[materials]]\nname = \"m\"\n  [[materials.relief]]\n";
  const Scene s = parse(head +
                        "  solid = { octaves = 2, seed = 4, space = \"world\" }\n"
                        "  amplitude = 0.02\n  scale = 6\n  split_octaves = true\n" +
                        kObject);
  ASSERT_EQ(s.materials[0].relief.size(), 2u);
  EXPECT_EQ(s.materials[0].relief[1].source, ReliefSource::Solid);
  EXPECT_TRUE(s.materials[0].relief[1].worldSpace);
  EXPECT_EQ(s.materials[0].relief[1].firstOctave, 1);
  EXPECT_FALSE(parse(head + "  solid = {}\n" + kObject).materials[0].relief[0].worldSpace);
  EXPECT_NE(errorOf(head + "  solid = { space = \"tangent\" }\n" + kObject)
                .find("materials.relief.solid.space"),
            std::string::npos);
  EXPECT_NE(errorOf(head + "  solid = {}\n  noise = {}\n" + kObject)
                .find("expected exactly one of `height` (an image file), `noise`"),
            std::string::npos);
  EXPECT_NE(errorOf(head + "  solid = {}\n  [[materials.relief]]\n  noise = {}\n" + kObject)
                .find("all `solid` (in one `space`) or none"),
            std::string::npos);
  EXPECT_NE(errorOf(head + "  solid = {}\n  [materials.ndf]\n  type = \"beckmann\"\n" + kObject)
                .find("materials.ndf: [materials.ndf] synthesizes detail over (u, v)"),
            std::string::npos);
}

TEST_F(SceneReaderTest, TableResolutionsAndTheirLimits) {
  const Scene s =
      parse(std::string(kObject) +
            "[render.tables]\ntheta_v_bins = 9\ntheta_n_bins = 48\nphi_bins = 16\nazimuths = 8\n"
            "rays_per_view = 512\nmesh_resolution = 64\nbrdf_theta_l = 12\nbrdf_phi = 10\nvariant "
            "= \"separable\"\nshadow_rays = 512\nframe_views = false\n");
  const TableResolution& t = s.render.tables;
  EXPECT_EQ(t.thetaVBins, 9);
  EXPECT_EQ(t.thetaNBins, 48);
  EXPECT_EQ(t.phiBins, 16);
  EXPECT_EQ(t.azimuths, 8);
  EXPECT_EQ(t.raysPerView, 512);
  EXPECT_EQ(t.meshResolution, 64);
  EXPECT_EQ(t.brdfThetaL, 12);
  EXPECT_EQ(t.brdfPhi, 10);
  EXPECT_EQ(t.variant, RedistributionVariant::Separable);
  EXPECT_EQ(t.shadowRays, 512);
  EXPECT_FALSE(t.frameViews);
  EXPECT_TRUE(parse(kObject).render.tables.frameViews);
  EXPECT_EQ(parse(kObject).render.tables.thetaNBins, 96);
  EXPECT_EQ(parse(kObject).render.tables.shadowRays, 128);
  EXPECT_NE(errorOf(std::string(kObject) + "[render.tables]\nshadow_rays = 8\n")
                .find(at(4, 15, "render.tables.shadow_rays") +
                      "expected an integer in [16, 4194304], got 8"),
            std::string::npos);
  EXPECT_NE(
      errorOf(std::string(kObject) + "[render.tables]\ntheta_v_bins = 1\n")
          .find(at(4, 16, "render.tables.theta_v_bins") + "expected an integer in [2, 90], got 1"),
      std::string::npos);
  EXPECT_NE(errorOf(std::string(kObject) + "[render.tables]\nrays = 3\n")
                .find(at(4, 1, "render.tables.rays") + "unknown key"),
            std::string::npos);
}

TEST_F(SceneReaderTest, NdfDeclarations) {
  const Scene s = parse(
      "[[materials]]\nname = \"m\"\n  [materials.ndf]\n  type = \"beckmann\"\n  alpha = [0.2, "
      "0.05]\n"
      "  angle = 30\n  scale = 64\n  octaves = 5\n  seed = 3\n  lambert = false\n" +
      std::string(kObject));
  const NdfDecl& n = s.materials[0].ndf;
  EXPECT_TRUE(n.present);
  EXPECT_EQ(n.type, NdfType::Beckmann);
  EXPECT_FLOAT_EQ(n.alpha.x, 0.2f);
  EXPECT_FLOAT_EQ(n.alpha.y, 0.05f);
  EXPECT_FLOAT_EQ(n.angle, 30.0f);
  EXPECT_FLOAT_EQ(n.scale, 64.0f);
  EXPECT_EQ(n.octaves, 5);
  EXPECT_EQ(n.seed, 3u);
  EXPECT_FALSE(n.lambert);
  EXPECT_FALSE(parse(kObject).materials[0].ndf.present);
  EXPECT_FLOAT_EQ(
      parse("[[materials]]\nname = \"m\"\n[materials.ndf]\nalpha = 0.4\n" + std::string(kObject))
          .materials[0]
          .ndf.alpha.y,
      0.4f);
  EXPECT_NE(errorOf("[[materials]]\nname = \"m\"\n[materials.ndf]\ntype = \"ggx\"\n" +
                    std::string(kObject))
                .find(at(4, 8, "materials.ndf.type") +
                      "expected one of beckmann | blinn-phong | tabulated | relief"),
            std::string::npos);
  EXPECT_NE(errorOf("[[materials]]\nname = \"m\"\n[materials.ndf]\ntype = \"tabulated\"\n" +
                    std::string(kObject))
                .find("materials.ndf.image: a tabulated NDF needs `image`"),
            std::string::npos);
  EXPECT_NE(errorOf("[[materials]]\nname = \"m\"\n[materials.ndf]\ntype = \"relief\"\n" +
                    std::string(kObject))
                .find("materials.ndf.type: \"relief\" estimates the NDF from the material's finest "
                      "relief level"),
            std::string::npos);
  EXPECT_NE(
      errorOf("[[materials]]\nname = \"m\"\n[materials.ndf]\nalpha = 0\n" + std::string(kObject))
          .find(at(4, 9, "materials.ndf.alpha") + "expected a number in [0.0001, 10]"),
      std::string::npos);
}

TEST_F(SceneReaderTest, MissingFilesAndBadCameraAreRejected) {
  EXPECT_NE(errorOf("[[objects]]\nmesh = \"nope.obj\"\n")
                .find(at(2, 8, "objects.mesh") + "file not found: "),
            std::string::npos);
  EXPECT_NE(
      errorOf("[[objects]]\nmesh = \".\"\n").find(at(2, 8, "objects.mesh") + "not a regular file"),
      std::string::npos);
  EXPECT_NE(errorOf("[render]\nseed = 1\n").find("objects: expected at least one [[objects]]"),
            std::string::npos);
  EXPECT_NE(
      errorOf(std::string(
                  "[[materials]]\nname = \"m\"\n[[materials.relief]]\nheight = \"gone.png\"\n") +
              kObject)
          .find(at(4, 10, "materials.relief.height") + "file not found"),
      std::string::npos);
  EXPECT_NE(errorOf(std::string("[camera]\nposition = [0, 0, 0]\nlook_at = [0, 0, 0]\n") + kObject)
                .find(at(3, 11, "camera.look_at") + "expected a point different"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string("[camera]\nposition = [0, 5, 0]\nlook_at = [0, 0, 0]\n") + kObject)
                .find("camera.up"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string("[[lights]]\ndirection = [0, 0, 0]\n") + kObject)
                .find(at(2, 13, "lights.direction")),
            std::string::npos);
  // A missing required key is located at its table's header.
  EXPECT_NE(errorOf("[render]\nseed = 1\n[[objects]]\nscheme = \"loop\"\n")
                .find(at(3, 1, "objects.mesh") + "every object needs a mesh file"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string("[[materials]]\nkd = 0.5\n") + kObject)
                .find(at(1, 1, "materials.name") + "every material needs a non-empty name"),
            std::string::npos);
  // A view direction that overflows single precision names the point that overflowed.
  EXPECT_NE(
      errorOf(std::string("[camera]\nposition = [0, 1e30, 1e30]\nlook_at = [0, 0, 0]\n") + kObject)
          .find(at(2, 12, "camera.position") + "expected a view direction"),
      std::string::npos);
}

// Keyframes that are each fine can interpolate to a frame that is not: through the look_at point,
// or over it with the up along the view. The scene is refused at the keys, not mid-render (an
// Embree assertion once aborted such a render).
TEST_F(SceneReaderTest, PathFramesThatAreNoCameraAreRejected) {
  const std::string through =
      "[path]\nframes = 3\n[[path.keys]]\ntime = 0\nposition = [0, 0.5, 5]\n"
      "look_at = [0, 0.5, 0]\n[[path.keys]]\ntime = 1\nposition = [0, 0.5, -5]\n"
      "look_at = [0, 0.5, 0]\n";
  EXPECT_NE(errorOf(through + kObject)
                .find(at(3, 1, "path.keys") + "frame 1 (time 0.5) is not a usable camera: the "
                                              "camera is at its look_at point"),
            std::string::npos);
  const std::string over =
      "[path]\nframes = 5\n[[path.keys]]\ntime = 0\nposition = [0, 3, 5]\n"
      "[[path.keys]]\ntime = 1\nposition = [0, 3, -5]\n";
  EXPECT_NE(errorOf(over + kObject).find("frame 2 (time 0.5) is not a usable camera: the up"),
            std::string::npos);
  // Four frames step over the middle: fine.
  const std::string four =
      "[path]\nframes = 4\n[[path.keys]]\ntime = 0\nposition = [0, 0.5, 5]\n"
      "look_at = [0, 0.5, 0]\n[[path.keys]]\ntime = 1\nposition = [0, 0.5, -5]\n"
      "look_at = [0, 0.5, 0]\n";
  EXPECT_EQ(parse(four + kObject).path.frames, 4);
}

TEST_F(SceneReaderTest, MalformedTomlNamesLineAndColumn) {
  const std::string e = errorOf("[camera\nfov = 3\n");
  EXPECT_EQ(e.rfind((dir_ / "scene.toml").string() + ":1:", 0), 0u) << e;
}

TEST_F(SceneReaderTest, MissingSceneFile) {
  try {
    loadScene(dir_ / "absent.toml");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("absent.toml: scene: file not found"), std::string::npos);
  }
}

}  // namespace
}  // namespace meso
