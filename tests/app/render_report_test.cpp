// What `meso render` says on stderr (src/app/render_report.cpp): "frame i of N" with the run's ETA
// before each frame of a path, and a last line naming every file written, the video included.
#include "support/run_meso.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace meso {
namespace {

namespace fs = std::filesystem;

using testing::RunResult;

class RenderReportTest : public testing::TempDirTest {
 protected:
  void SetUp() override {
    testing::TempDirTest::SetUp();
    write("quad.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
    const std::string still =
        "[camera]\nposition = [0.4, -2.5, 2]\nup = [0, 0, 1]\nresolution = [24, 16]\nspp = 1\n"
        "[[lights]]\ndirection = [0.3, 0.2, -1]\n[[objects]]\nmesh = \"quad.obj\"\n"
        "scheme = \"bilinear\"\n";
    write("still.toml", still);
    write("path.toml", still +
                           "[path]\nframes = 3\n[[path.keys]]\ntime = 0\n[[path.keys]]\ntime = 1\n"
                           "position = [0.6, -2.5, 2]\n");
  }
  RunResult render(const std::string& scene, const std::string& args) {
    return testing::runMeso("render " + (dir_ / scene).string() + " -o " + out("f.exr") + " " +
                            args);
  }
  std::string out(const std::string& name) const { return (dir_ / "out" / name).string(); }
  // The last line of the output.
  static std::string lastLine(const std::string& output) {
    const size_t end = output.find_last_not_of('\n');
    const size_t start = output.rfind('\n', end);
    return output.substr(start == std::string::npos ? 0 : start + 1, end + 1 - (start + 1));
  }
};

TEST_F(RenderReportTest, AStillNamesItsFiles) {
  RunResult r = render("still.toml", "--stats " + out("s.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(lastLine(r.output),
            "meso: wrote " + out("f.exr") + ", " + out("f.png") + " and " + out("s.json"));
  for (const char* f : {"f.exr", "f.png", "s.json"}) EXPECT_TRUE(fs::exists(out(f))) << f;
  EXPECT_EQ(r.output.find("frame 1 of"), std::string::npos) << "a still has no frame count";
  r = render("still.toml", "-q");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output, "") << "-q: no summary";
}

TEST_F(RenderReportTest, APathCountsItsFramesAndNamesEveryFile) {
  RunResult r = render("path.toml", "--stats " + out("s.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("meso: frame 1 of 3 (path frame 0 of 3), elapsed 0:0"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find(", ETA ?\n"), std::string::npos) << "no estimate before a frame is done";
  EXPECT_NE(r.output.find("meso: frame 3 of 3 (path frame 2 of 3), elapsed 0:0"), std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("frame 4 of"), std::string::npos) << r.output;
  EXPECT_EQ(lastLine(r.output), "meso: wrote 3 frames (" + out("f_0000.exr") + " to " +
                                    out("f_0002.exr") + ", each with its .png) and " +
                                    out("s.json"));
  // A resumed run counts only the frames it renders; one frame is named with its PNG.
  fs::remove(out("f_0001.exr"));
  r = render("path.toml", "");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("meso: frame 1 of 1 (path frame 1 of 3), elapsed "), std::string::npos)
      << r.output;
  EXPECT_EQ(lastLine(r.output), "meso: wrote " + out("f_0001.exr") + " and " + out("f_0001.png"));
  r = render("path.toml", "");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(lastLine(r.output), "meso: wrote no file");
}

TEST_F(RenderReportTest, TheVideoIsNamed) {
  if (testing::runMeso("render " + (dir_ / "path.toml").string() + " -q --video " + out("v.mp4") +
                       " -o " + out("probe.exr"))
          .status != 0)
    GTEST_SKIP() << "no ffmpeg with libx264";
  const RunResult r = render("path.toml", "--video " + out("v.mp4") + " --overwrite");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(lastLine(r.output), "meso: wrote 3 frames (" + out("f_0000.exr") + " to " +
                                    out("f_0002.exr") + ", each with its .png) and " +
                                    out("v.mp4"));
}

}  // namespace
}  // namespace meso
