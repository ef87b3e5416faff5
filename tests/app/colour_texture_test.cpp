// Colour textures in renders (kd and ks images): a constant image is its colour bit for bit, a
// checker on a grazing plane filtered at 4 spp matches many point-sampled samples per pixel, and
// bad images are errors naming the file and the key.
#include "meso/core/image_io.h"
#include "meso/core/math.h"

#include "support/run_meso.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>

namespace meso {
namespace {

namespace fs = std::filesystem;
using meso::testing::runMeso;

class ColourTextureTest : public meso::testing::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    write("plane.obj",
          "v -10 0 -10\nv 10 0 -10\nv 10 0 10\nv -10 0 10\nvt 0 0\nvt 8 0\nvt 8 8\nvt 0 8\n"
          "f 1/1 4/4 3/3 2/2\n");
  }
  // A grazing view of the plane with kd (a TOML value) and ks 0.2.
  fs::path scene(const std::string& name, const std::string& kd) const {
    return write(name,
                 "[camera]\nposition = [0, 0.5, 10]\nlook_at = [0, 0, 0]\nfov = 30\n"
                 "resolution = [96, 54]\nspp = 4\n[[lights]]\ndirection = [0.3, -0.6, -1]\n"
                 "[[materials]]\nname = \"m\"\nkd = " +
                     kd +
                     "\nks = 0.2\n[[objects]]\nmesh = \"plane.obj\"\nscheme = "
                     "\"bilinear\"\nmaterial = \"m\"\n[render]\nbackground = [0.5, 0.6, "
                     "0.8]\ncache_dir = \"" +
                     (dir_ / "cache").string() + "\"\n");
  }
  Image render(const fs::path& scene, const std::string& name, const std::string& extra = "") {
    const fs::path out = dir_ / name;
    const auto r = runMeso("render " + scene.string() + " -q -o " + out.string() + " " + extra);
    EXPECT_EQ(r.status, 0) << r.output;
    return readImage(out);
  }
  void rgbImage(const std::string& name, int w, int h, Vec3 (*f)(int, int)) const {
    Image img(w, h, {"R", "G", "B"});
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int k = 0; k < 3; ++k) img.at(x, y, k) = f(x, y)[k];
    writeExr(dir_ / name, img);
  }
};

TEST_F(ColourTextureTest, ConstantImageGivesTheConstantKdBitForBit) {
  rgbImage("c.exr", 16, 16, [](int, int) { return Vec3(0.5f, 0.25f, 0.125f); });
  const Image a = render(scene("a.toml", "\"c.exr\""), "a.exr");
  const Image b = render(scene("b.toml", "[0.5, 0.25, 0.125]"), "b.exr");
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  int lit = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int k = 0; k < 3; ++k) {
        ASSERT_EQ(a.at(x, y, k), b.at(x, y, k)) << x << " " << y;
        lit += k == 0 && a.at(x, y, k) > 0.0f && a.at(x, y, k) != 0.5f;  // not background
      }
  EXPECT_GT(lit, 1000);
}

// The checker's filtered lookups at 4 spp against point lookups at 256 spp, per band of 6 rows of
// the plane: within 1%. Point lookups at 4 spp alias where the checks are below a pixel.
TEST_F(ColourTextureTest, FilteredCheckerMatchesManyPointSamples) {
  rgbImage("checker.exr", 64, 64, [](int x, int y) {
    return ((x / 8 + y / 8) % 2) ? Vec3(0.9f, 0.8f, 0.6f) : Vec3(0.05f);
  });
  const fs::path s = scene("checker.toml", "\"checker.exr\"");
  const Image filtered = render(s, "f.exr");
  const Image reference = render(s, "r.exr", "--spp 256 --no-texture-filter");
  const Image point = render(s, "p.exr", "--no-texture-filter");
  const int depth = reference.channelIndex("depth.Z");
  ASSERT_GE(depth, 0);
  double worstFiltered = 0.0, worstPoint = 0.0;
  for (int band = 0; band * 6 < reference.height; ++band) {
    double f = 0.0, r = 0.0, p = 0.0;
    int n = 0;
    for (int y = band * 6; y < std::min(reference.height, band * 6 + 6); ++y)
      for (int x = 0; x < reference.width; ++x) {
        if (!(reference.at(x, y, depth) > 0.0f)) continue;  // the plane only
        for (int k = 0; k < 3; ++k)
          f += filtered.at(x, y, k), r += reference.at(x, y, k), p += point.at(x, y, k);
        ++n;
      }
    if (n < 50) continue;
    worstFiltered = std::max(worstFiltered, std::abs(f / r - 1.0));
    worstPoint = std::max(worstPoint, std::abs(p / r - 1.0));
  }
  std::printf("[ figure ] worst band: filtered 4 spp %.3f%%, point 4 spp %.3f%%\n",
              100.0 * worstFiltered, 100.0 * worstPoint);
  EXPECT_LT(worstFiltered, 0.01);
  EXPECT_GT(worstPoint, worstFiltered);  // filtering is what keeps it there
}

TEST_F(ColourTextureTest, BadImagesAreErrorsNamingTheFileAndKey) {
  rgbImage("nan.exr", 4, 4, [](int x, int) {
    return Vec3(x == 2 ? std::numeric_limits<float>::quiet_NaN() : 0.5f);
  });
  write("text.png", "not an image");
  for (const auto& [file, what] :
       {std::pair{"nan.exr", "NaN or infinite"}, std::pair{"text.png", "not an image"}}) {
    const fs::path out = dir_ / "out" / "x.exr";
    const auto r = runMeso("render " + scene("bad.toml", std::string("\"") + file + "\"").string() +
                           " -q -o " + out.string());
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("materials.kd"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(file), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(what), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
  }
  const auto missing = runMeso("render " + scene("m.toml", "\"none.png\"").string() + " -q -o " +
                               (dir_ / "m.exr").string());
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.output.find("file not found"), std::string::npos) << missing.output;
}

}  // namespace
}  // namespace meso
