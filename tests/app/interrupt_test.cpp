// Fly-throughs stopped by real signals, sent to the meso executable started with posix_spawn:
// SIGINT exits with status 130 leaving only complete frames and no temporary file; SIGKILL (no
// clean-up possible) never leaves a partial frame under a final name, and a rerun completes the
// path, skipping the frames that were complete.
#include "meso/core/error.h"
#include "meso/core/image_io.h"
#include "meso/render/film_layout.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr int kFrames = 60;
constexpr int kWidth = 96, kHeight = 54;

std::string readAll(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// A child process running meso with stdout to /dev/null and stderr to a file. Signals the test
// process ignores or blocks are reset to their defaults in the child.
class Child {
 public:
  Child(const std::vector<std::string>& args, const fs::path& stderrFile) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, stderrFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    sigset_t defaults, empty;
    sigemptyset(&defaults);
    sigaddset(&defaults, SIGINT);
    sigaddset(&defaults, SIGTERM);
    sigemptyset(&empty);
    posix_spawnattr_setsigdefault(&attr, &defaults);
    posix_spawnattr_setsigmask(&attr, &empty);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);
    std::vector<std::string> all = {MESO_EXE};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    spawnError_ = posix_spawn(&pid_, MESO_EXE, &actions, &attr, argv.data(), environ);
    posix_spawnattr_destroy(&attr);
    posix_spawn_file_actions_destroy(&actions);
  }
  ~Child() {
    if (running()) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  bool started() const { return spawnError_ == 0; }
  bool running() const { return spawnError_ == 0 && !reaped_; }
  void signal(int sig) const { ::kill(pid_, sig); }
  // The raw wait status, or -1 after `timeout` (the child is then killed).
  int wait(std::chrono::seconds timeout) {
    const auto end = Clock::now() + timeout;
    int status = 0;
    while (Clock::now() < end) {
      const pid_t r = ::waitpid(pid_, &status, WNOHANG);
      if (r == pid_) {
        reaped_ = true;
        return status;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return -1;
  }

 private:
  pid_t pid_ = -1;
  int spawnError_ = -1;
  bool reaped_ = false;
};

class InterruptTest : public meso::testing::TempDirTest {
 protected:
  void SetUp() override {
    meso::testing::TempDirTest::SetUp();
    write("plane.obj",
          "v -2 -2 0\nv 2 -2 0\nv 2 2 0\nv -2 2 0\nvt 0 0\nvt 1 "
          "0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n");
    // A plane with noise relief flown over from far (BRDF) to close (displaced micropolygons), so
    // frames differ in cost and content. Small tables, cached in the temporary folder.
    write("fly.toml", "[camera]\nresolution = [" + std::to_string(kWidth) + ", " +
                          std::to_string(kHeight) +
                          "]\nspp = 4\n"
                          "[path]\nframes = " +
                          std::to_string(kFrames) +
                          "\n"
                          "[[path.keys]]\ntime = 0.0\nposition = [0.0, -6.0, "
                          "5.0]\nlook_at = [0.0, 0.0, 0.0]\n"
                          "[[path.keys]]\ntime = 1.0\nposition = [0.5, -2.0, "
                          "1.0]\nlook_at = [0.0, 0.5, 0.0]\n"
                          "[[path.keys]]\ntime = 2.0\nposition = [0.2, -0.6, "
                          "0.3]\nlook_at = [0.0, 0.6, 0.0]\n"
                          "[[lights]]\ndirection = [0.2, 0.7, -0.6]\n"
                          "[[materials]]\nname = \"m\"\nks = 0.2\n"
                          "  [[materials.relief]]\n  noise = { octaves = 2 }\n "
                          " amplitude = 0.01\n  scale = 8.0\n"
                          "[[objects]]\nmesh = \"plane.obj\"\nscheme = "
                          "\"bilinear\"\nmaterial = \"m\"\n"
                          "[render]\nseed = 3\nthreads = 1\ntessellation_rate "
                          "= 2\ndicing_rate = 2.0\n"
                          "cache_dir = \"" +
                          (dir_ / "cache").string() +
                          "\"\n"
                          "[render.tables]\ntheta_v_bins = 4\ntheta_n_bins = "
                          "16\nphi_bins = 8\nazimuths = 4\n"
                          "rays_per_view = 64\nmesh_resolution = "
                          "16\nbrdf_theta_l = 4\nbrdf_phi = 4\n");
    fs::create_directories(dir_ / "out");
  }

  std::vector<std::string> args(bool quiet = true) const {
    std::vector<std::string> a = {"render", (dir_ / "fly.toml").string(), "-o",
                                  (dir_ / "out/f.exr").string()};
    if (quiet) a.push_back("-q");
    return a;
  }

  static fs::path frameFile(int f, const char* ext) {
    char name[32];
    std::snprintf(name, sizeof name, "f_%04d.%s", f, ext);
    return name;
  }

  // Waits (up to 60 s) until frame `f` exists under both final names.
  bool waitForFrame(int f) const {
    const auto end = Clock::now() + std::chrono::seconds(60);
    while (Clock::now() < end) {
      if (fs::exists(dir_ / "out" / frameFile(f, "exr")) &&
          fs::exists(dir_ / "out" / frameFile(f, "png")))
        return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return false;
  }

  // Every file under a final frame name must read back as a whole kWidth x kHeight image with the
  // expected channels. Returns the frames (numbers) whose EXR and PNG are both on disk, and counts
  // the temporaries (.NAME.tmp-PID-N.ext); the path's settings file (.f.meso-settings) is neither.
  std::set<int> checkFinalFrames(int* temporaries) const {
    std::set<int> exr, png;
    *temporaries = 0;
    for (const auto& e : fs::directory_iterator(dir_ / "out")) {
      const std::string name = e.path().filename().string();
      if (name == ".f.meso-settings") continue;
      if (name[0] == '.') {
        ++*temporaries;
        continue;
      }
      int frame = -1;
      char ext[8] = {};
      EXPECT_EQ(std::sscanf(name.c_str(), "f_%4d.%3s", &frame, ext), 2)
          << "unexpected file " << name;
      EXPECT_EQ(name, frameFile(frame, ext).string()) << "unexpected file " << name;
      try {
        const meso::Image img = meso::readImage(e.path());
        EXPECT_EQ(img.width, kWidth) << name;
        EXPECT_EQ(img.height, kHeight) << name;
        EXPECT_EQ(img.pixels.size(), size_t(kWidth) * kHeight * img.channels.size()) << name;
        if (std::string(ext) == "exr") {
          EXPECT_NO_THROW(meso::FilmLayout::fromExr(img, name)) << "an EXR without all its layers";
          exr.insert(frame);
        } else {
          EXPECT_GE(img.numChannels(), 3) << name;
          png.insert(frame);
        }
      } catch (const meso::Error& err) {
        ADD_FAILURE() << "a partial frame under a final name: " << err.what();
      }
    }
    std::set<int> both;
    for (int f : exr)
      if (png.count(f)) both.insert(f);
    return both;
  }
};

TEST_F(InterruptTest, SigintExits130WithOnlyCompleteFramesAndNoTemporaries) {
  Child child(args(), dir_ / "stderr.txt");
  ASSERT_TRUE(child.started());
  ASSERT_TRUE(waitForFrame(1)) << "no frame within 60 s: " << readAll(dir_ / "stderr.txt");
  child.signal(SIGINT);
  const int status = child.wait(std::chrono::seconds(60));
  ASSERT_NE(status, -1) << "meso did not stop within 60 s of SIGINT";
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal "
                                 << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  EXPECT_EQ(WEXITSTATUS(status), 130) << readAll(dir_ / "stderr.txt");
  int temporaries = 0;
  const std::set<int> complete = checkFinalFrames(&temporaries);
  EXPECT_EQ(temporaries, 0) << "temporary files left behind after SIGINT";
  EXPECT_GE(complete.size(), 2u);
  EXPECT_LT(complete.size(), size_t(kFrames)) << "the interrupt came too late to test anything";
  // Frames are written in order: what is on disk is frames 0..n-1, each as an EXR and PNG pair.
  int expected = 0;
  for (int f : complete) EXPECT_EQ(f, expected++);
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir_ / "out"))
    files += e.is_regular_file() && e.path().filename() != ".f.meso-settings";
  EXPECT_EQ(files, 2 * complete.size()) << "an EXR without its PNG (or the reverse)";
}

// SIGKILL at several moments after a frame appears (to land in a render and, sometimes, in a
// write): final names only ever hold whole frames; then a rerun finishes the path, skipping (and
// not rewriting) the frames that were complete.
TEST_F(InterruptTest, SigkillLeavesNoPartialFrameAndRerunCompletes) {
  int killedAt = 1;
  for (int delayMs : {0, 3, 11}) {
    Child child(args(), dir_ / "stderr.txt");
    ASSERT_TRUE(child.started());
    ASSERT_TRUE(waitForFrame(killedAt))
        << "no new frame within 60 s: " << readAll(dir_ / "stderr.txt");
    std::this_thread::sleep_for(std::chrono::milliseconds(delayMs));
    child.signal(SIGKILL);
    const int status = child.wait(std::chrono::seconds(60));
    ASSERT_NE(status, -1);
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL)
        << "finished before SIGKILL: raise kFrames";
    int temporaries = 0;
    const std::set<int> complete = checkFinalFrames(&temporaries);
    ASSERT_LT(complete.size(), size_t(kFrames));
    killedAt = static_cast<int>(complete.size()) + 1;  // the next run must get further
  }

  int temporaries = 0;
  const std::set<int> before = checkFinalFrames(&temporaries);
  std::map<int, fs::file_time_type> stamps;
  for (int f : before) stamps[f] = fs::last_write_time(dir_ / "out" / frameFile(f, "exr"));
  ASSERT_GE(before.size(), 3u);

  Child rerun(args(/*quiet=*/false), dir_ / "stderr.txt");
  ASSERT_TRUE(rerun.started());
  const int status = rerun.wait(std::chrono::seconds(120));
  ASSERT_NE(status, -1) << "the rerun did not finish within 120 s";
  const std::string err = readAll(dir_ / "stderr.txt");
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << err;
  EXPECT_NE(err.find("skipped " + std::to_string(before.size()) + " frame(s)"), std::string::npos)
      << err;
  const std::set<int> after = checkFinalFrames(&temporaries);
  EXPECT_EQ(after.size(), size_t(kFrames)) << "the rerun must complete the path";
  for (const auto& [f, stamp] : stamps)
    EXPECT_EQ(fs::last_write_time(dir_ / "out" / frameFile(f, "exr")), stamp)
        << "frame " << f << " was redone";
  if (temporaries > 0)
    std::printf(
        "note: %d temporary file(s) of the killed runs remain (SIGKILL "
        "allows no clean-up)\n",
        temporaries);
}

}  // namespace
