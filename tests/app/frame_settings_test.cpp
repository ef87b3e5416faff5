// A path resumed with other settings (src/app/frame_settings.cpp): refused with exit status 2 and
// the settings that differ named, unless --overwrite; the same settings resume, and settings that
// leave the pixels alone (threads) do not count.
#include "support/run_meso.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

namespace meso {
namespace {

namespace fs = std::filesystem;

using testing::RunResult;

class FrameSettingsTest : public testing::TempDirTest {
 protected:
  void SetUp() override {
    testing::TempDirTest::SetUp();
    write("quad.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
    write("path.toml",
          "[camera]\nposition = [0.4, -2.5, 2]\nup = [0, 0, 1]\nresolution = [16, 12]\nspp = 1\n"
          "[[lights]]\ndirection = [0.3, 0.2, -1]\n[[objects]]\nmesh = \"quad.obj\"\n"
          "scheme = \"bilinear\"\n[path]\nframes = 2\n[[path.keys]]\ntime = 0\n"
          "[[path.keys]]\ntime = 1\nposition = [0.6, -2.5, 2]\n");
  }
  RunResult render(const std::string& args) {
    return testing::runMeso("render " + (dir_ / "path.toml").string() + " -q -o " + out("f.exr") +
                            " " + args);
  }
  std::string out(const std::string& name) const { return (dir_ / "out" / name).string(); }
  nlohmann::json stored() const {
    std::ifstream in(out(".f.meso-settings"));
    return nlohmann::json::parse(in);
  }
  void expectRefused(const std::string& args, const std::string& difference) {
    const auto before = fs::last_write_time(out("f_0000.exr"));
    const RunResult r = render(args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.output;
    EXPECT_EQ(r.output.rfind("meso: " + out(".f.meso-settings") + ": the frames of " +
                                 out("f.exr") + " on disk were rendered with other settings (",
                             0),
              0)
        << args << ": " << r.output;
    EXPECT_NE(r.output.find(difference), std::string::npos) << args << ": " << r.output;
    EXPECT_NE(r.output.find("): pass --overwrite to render every frame again"), std::string::npos)
        << r.output;
    EXPECT_EQ(fs::last_write_time(out("f_0000.exr")), before) << args << ": a frame was rewritten";
  }
};

TEST_F(FrameSettingsTest, OtherSettingsAreRefusedUnlessOverwrite) {
  RunResult r = render("");
  ASSERT_EQ(r.status, 0) << r.output;
  ASSERT_TRUE(fs::exists(out("f_0001.png")));
  EXPECT_EQ(stored()["spp"], 1);
  fs::remove(out("f_0001.exr"));
  expectRefused("--spp 2", "spp 1 (now 2)");
  expectRefused("--set render.D=3", "set [] (now [\"render.D=3\"])");
  expectRefused("--set render.D=3", "transition.D 2 (now 3)");
  expectRefused("--false-colour", "false_colour false (now true)");
  expectRefused("--no-texture-filter", "texture_filter true (now false)");
  expectRefused("--crop 0,0,8,8", "crop null (now [0,0,8,8])");
  expectRefused("--eps 0.3", "transition.eps 0.1 (now 0.3)");
  // The same settings, and a thread count (the image does not depend on it), resume the path.
  r = testing::runMeso("render " + (dir_ / "path.toml").string() + " -o " + out("f.exr") +
                       " --threads 1");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("meso: frame 1 of 1 (path frame 1 of 2)"), std::string::npos) << r.output;
  // --overwrite renders every frame again and keeps the new settings.
  r = render("--spp 2 --overwrite");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(stored()["spp"], 2);
  EXPECT_EQ(render("--spp 2").status, 0);
  expectRefused("", "spp 2 (now 1)");
  // The scene file's text, also where no reported setting shows it (a material's colour).
  std::ofstream(dir_ / "path.toml", std::ios::app) << "[[materials]]\nname = \"m\"\nkd = 0.2\n";
  expectRefused("--spp 2", "(the scene file's text)");
  for (const auto& e : fs::directory_iterator(dir_ / "out"))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}

// Without frames on disk any settings start the path afresh; a still keeps no settings file.
TEST_F(FrameSettingsTest, NoFramesNoRefusalAndNoFileForAStill) {
  ASSERT_EQ(render("").status, 0);
  fs::remove(out("f_0000.exr")), fs::remove(out("f_0000.png"));
  fs::remove(out("f_0001.exr")), fs::remove(out("f_0001.png"));
  const RunResult r = render("--spp 3");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(stored()["spp"], 3);
  write("still.toml",
        "[camera]\nresolution = [8, 8]\nposition = [0, 0, 3]\n[[objects]]\n"
        "mesh = \"quad.obj\"\n[[lights]]\n");
  ASSERT_EQ(testing::runMeso("render " + (dir_ / "still.toml").string() + " -q -o " + out("s.exr"))
                .status,
            0);
  EXPECT_TRUE(fs::exists(out("s.exr")));
  EXPECT_FALSE(fs::exists(out(".s.meso-settings")));
}

}  // namespace
}  // namespace meso
