// A height image in a scene is split into band-limited levels by default (relief_bands.h).
#include "meso/core/error.h"
#include "meso/core/image_io.h"
#include "meso/core/math.h"
#include "meso/scene/relief_bands.h"
#include "meso/scene/scene_parser.h"

#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace meso {
namespace {

class ReliefBandsTest : public testing::TempDirTest {
 protected:
  // A 64 x 64 grey EXR (linear: a PNG's sRGB curve would add harmonics) of waves along x at 2 and
  // 24 cycles, of equal slope amplitude.
  void SetUp() override {
    TempDirTest::SetUp();
    write("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
    Image img(64, 64, {"R", "G", "B"});
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        const float u = (x + 0.5f) / 64.0f;
        const float h =
            0.5f + 0.3f * std::sin(2 * kPi * 2 * u) + 0.025f * std::sin(2 * kPi * 24 * u);
        for (int c = 0; c < 3; ++c) img.at(x, y, c) = h;
      }
    writeExr(dir_ / "waves.exr", img);
  }
  // The scene as `meso` loads it (loadScene plans the bands; parseScene reads no image).
  Scene parse(const std::string& relief) {
    write("scene.toml",
          "[[materials]]\nname = \"m\"\n[[materials.relief]]\nheight = \"waves.exr\"\n"
          "amplitude = 0.1\n" +
              relief + "[[objects]]\nmesh = \"quad.obj\"\nmaterial = \"m\"\n");
    return loadScene(dir_ / "scene.toml");
  }
};

// Two waves an order of magnitude apart in frequency and of equal slope: two levels, coarse first,
// covering every band once; the midlevel stays on the coarse one.
TEST_F(ReliefBandsTest, AnImageOfTwoScalesIsTwoLevels) {
  const Scene s = parse("midlevel = 0.4\n");
  const std::vector<ReliefLevelDecl>& r = s.materials[0].relief;
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].bandCount, r[1].bandCount);
  EXPECT_GT(r[0].bandCount, 2);
  EXPECT_EQ(r[0].bandFirst, 0);
  EXPECT_EQ(r[1].bandFirst, r[0].bandLast + 1);
  EXPECT_EQ(r[1].bandLast, r[1].bandCount - 1);
  ASSERT_TRUE(r[0].midlevel.has_value());
  EXPECT_FLOAT_EQ(*r[0].midlevel, 0.4f);
  EXPECT_FALSE(r[1].midlevel.has_value());
  for (const ReliefLevelDecl& d : r) EXPECT_EQ(d.height, dir_ / "waves.exr");
}

// bands = 1 keeps the image one level; a hand-set freq does too; both at once with more bands is
// refused at the freq key.
TEST_F(ReliefBandsTest, OneLevelOnRequest) {
  EXPECT_EQ(parse("bands = 1\n").materials[0].relief.size(), 1u);
  EXPECT_EQ(parse("bands = 1\n").materials[0].relief[0].bandCount, 1);
  EXPECT_EQ(parse("freq = 30\n").materials[0].relief.size(), 1u);
  try {
    parse("bands = 3\nfreq = 30\n");
    ADD_FAILURE() << "bands = 3 with freq accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("relief.freq: "), std::string::npos) << e.what();
  }
}

// A level budget: other relief tables of the material leave the image fewer levels.
TEST_F(ReliefBandsTest, BandsShareTheMaterialsLevelBudget) {
  std::string others;
  for (int k = 0; k < 7; ++k) others += "[[materials.relief]]\nnoise = {}\namplitude = 0.01\n";
  EXPECT_EQ(parse(others).materials[0].relief.size(), 8u);
}

}  // namespace
}  // namespace meso

namespace meso {
namespace {

// Parsing reads no image: the parser (fuzzed with any text) stays a parser, and a scene parsed
// from text keeps one level per image until expandImageBands.
TEST_F(ReliefBandsTest, ParsingAloneReadsNoImage) {
  const std::string text =
      "[[materials]]\nname = \"m\"\n[[materials.relief]]\nheight = \"waves.exr\"\n"
      "amplitude = 0.1\n[[objects]]\nmesh = \"quad.obj\"\nmaterial = \"m\"\n";
  Scene s = parseScene(text, dir_ / "scene.toml");
  ASSERT_EQ(s.materials[0].relief.size(), 1u);
  expandImageBands(s);
  EXPECT_EQ(s.materials[0].relief.size(), 2u);
  expandImageBands(s);  // once planned, the levels stay as they are
  EXPECT_EQ(s.materials[0].relief.size(), 2u);
}

}  // namespace
}  // namespace meso
