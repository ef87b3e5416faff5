// Bad environment maps through the CLI: a missing, non-image, zero-size, NaN or negative map is an
// error naming the file and the light's key, exit 2, nothing written.
#include "meso/core/image_io.h"
#include "meso/core/math.h"

#include "support/run_meso.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <limits>
#include <string>

namespace meso {
namespace {

namespace fs = std::filesystem;
using meso::testing::runMeso;

class EnvironmentInputTest : public meso::testing::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    write("plane.obj", "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nf 1 4 3 2\n");
  }
  fs::path scene(const std::string& environment) const {
    return write("scene.toml",
                 "[camera]\nposition = [0, 2, 3]\nlook_at = [0, 0, 0]\nresolution = [24, 16]\n"
                 "spp = 1\n[[lights]]\ntype = \"environment\"\nenvironment = \"" +
                     environment +
                     "\"\n[[objects]]\nmesh = \"plane.obj\"\nscheme = \"bilinear\"\n[render]\n"
                     "light_samples = 4\ncache_dir = \"" +
                     (dir_ / "cache").string() + "\"\n");
  }
  void map(const std::string& name, float bad) const {
    Image img(8, 4, {"R", "G", "B"});
    for (float& v : img.pixels) v = 1.0f;
    img.at(5, 2, 1) = bad;
    writeExr(dir_ / name, img);
  }
};

TEST_F(EnvironmentInputTest, BadMapsAreErrorsNamingTheFile) {
  map("nan.exr", std::numeric_limits<float>::quiet_NaN());
  map("negative.exr", -0.5f);
  write("text.hdr", "not an image");
  write("empty.exr", "");
  map("good.exr", 2.0f);
  for (const auto& [file, what] :
       {std::pair{"nan.exr", "NaN or infinite"}, std::pair{"negative.exr", "is negative"},
        std::pair{"text.hdr", "not an image"}, std::pair{"empty.exr", "not an image"},
        std::pair{"missing.exr", "file not found"}}) {
    const fs::path out = dir_ / "out" / "x.exr";
    const auto r = runMeso("render " + scene(file).string() + " -q -o " + out.string());
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("lights.environment"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(file), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(what), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out)) << file;
    EXPECT_FALSE(fs::exists(dir_ / "out" / "x.png")) << file;
  }
  const fs::path out = dir_ / "good.exr.out.exr";
  const auto r = runMeso("render " + scene("good.exr").string() + " -q -o " + out.string());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(out));
}

}  // namespace
}  // namespace meso
