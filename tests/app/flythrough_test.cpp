// Fly-throughs as a farm would run them: shards give exactly the frames of one run, complete
// frames are skipped on a rerun, and an interrupt leaves no partial frame (tested with a real
// signal).
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

namespace {

namespace fs = std::filesystem;

int runCommand(const std::string& args) {
  const int raw = std::system((std::string(MESO_EXE) + " " + args + " >/dev/null 2>&1").c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

std::string readAll(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

class FlythroughTest : public meso::testing::TempDirTest {
 protected:
  std::string args(const std::string& out, const std::string& extra,
                   const std::string& quality = "--width 48 --height 27 --spp 2") const {
    return "render " + std::string(MESO_SOURCE_DIR) + "/scenes/flythrough.toml -o " +
           (dir_ / out).string() + " " + quality + " -q " + extra;
  }
};

TEST_F(FlythroughTest, ShardsGiveTheFramesOfOneRunBitForBit) {
  ASSERT_EQ(runCommand(args("one/f.exr", "--frames 0:7")), 0);
  ASSERT_EQ(runCommand(args("two/f.exr", "--frames 0:7 --shard 0/2")), 0);
  ASSERT_EQ(runCommand(args("two/f.exr", "--frames 0:7 --shard 1/2 --threads 1")), 0);
  int compared = 0;
  for (const auto& e : fs::directory_iterator(dir_ / "one")) {
    const fs::path other = dir_ / "two" / e.path().filename();
    ASSERT_TRUE(fs::exists(other)) << other;
    if (e.path().extension() == ".exr") {
      EXPECT_TRUE(readAll(e.path()) == readAll(other)) << e.path().filename();
      ++compared;
    }
  }
  EXPECT_EQ(compared, 8);
  // Frames differ from each other (the camera moves), so equality above is not vacuous.
  EXPECT_FALSE(readAll(dir_ / "one/f_0000.exr") == readAll(dir_ / "one/f_0007.exr"));
}

TEST_F(FlythroughTest, RerunSkipsCompleteFramesUnlessOverwrite) {
  ASSERT_EQ(runCommand(args("f.exr", "--frames 2:4")), 0);
  const auto stamp = fs::last_write_time(dir_ / "f_0003.exr");
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  fs::remove(dir_ / "f_0004.png");  // an incomplete frame is redone
  ASSERT_EQ(runCommand(args("f.exr", "--frames 2:4 --stats " + (dir_ / "s.json").string())), 0);
  EXPECT_EQ(fs::last_write_time(dir_ / "f_0003.exr"), stamp);
  EXPECT_TRUE(fs::exists(dir_ / "f_0004.png"));
  const std::string stats = readAll(dir_ / "s.json");
  EXPECT_NE(stats.find("\"frames_skipped\": 2"), std::string::npos) << stats;
  EXPECT_NE(stats.find("\"frames_rendered\": 1"), std::string::npos) << stats;
  ASSERT_EQ(runCommand(args("f.exr", "--frames 2:4 --overwrite")), 0);
  EXPECT_NE(fs::last_write_time(dir_ / "f_0003.exr"), stamp);
}

TEST_F(FlythroughTest, BadFrameRangesAndShardsAreErrors) {
  EXPECT_EQ(runCommand(args("f.exr", "--frames 5:2")), 2);
  EXPECT_EQ(runCommand(args("f.exr", "--frames 0:48")), 2);
  EXPECT_EQ(runCommand(args("f.exr", "--shard 2/2")), 2);
  EXPECT_EQ(runCommand(args("f.exr", "--shard x")), 2);
  EXPECT_TRUE(fs::is_empty(dir_));
}

// SIGINT during a long path: status 130, every file under a final name is a complete frame pair
// (EXR and PNG) and no temporary is left; a rerun completes the path.
TEST_F(FlythroughTest, InterruptLeavesNoPartialFrameAndRerunCompletes) {
  const std::string cmd =
      std::string(MESO_EXE) + " " + args("f.exr", "", "--spp 16 --width 160 --height 90");
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", ("exec " + cmd + " >/dev/null 2>&1").c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  // Wait until the first frame is complete, then interrupt mid-path.
  for (int i = 0; i < 600 && !fs::exists(dir_ / "f_0001.png"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  int exr = 0;
  for (const auto& e : fs::directory_iterator(dir_)) {
    const std::string name = e.path().filename().string();
    EXPECT_EQ(name.find(".tmp-"), std::string::npos) << "temporary left behind: " << name;
    if (e.path().extension() == ".exr") {
      ++exr;
      fs::path png = e.path();
      EXPECT_TRUE(fs::exists(png.replace_extension(".png"))) << name;
    }
  }
  EXPECT_LT(exr, 48) << "the interrupt came too late to test anything";
  ASSERT_EQ(runCommand(args("f.exr", "", "--spp 16 --width 160 --height 90")), 0);
  int after = 0;
  for (const auto& e : fs::directory_iterator(dir_)) after += e.path().extension() == ".exr";
  EXPECT_EQ(after, 48);
}

}  // namespace
