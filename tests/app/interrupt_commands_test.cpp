// Every command stops within 0.5 s of SIGINT or SIGTERM with status 128 + the signal (130, 143) and
// no partial output, also inside loops that do not poll for cancellation (table building, the patch
// consistency study, band splitting, tessellation): the interrupt watchdog ends them after its
// grace period.
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

class InterruptCommandsTest : public meso::testing::TempDirTest {
 protected:
  void SetUp() override {
    meso::testing::TempDirTest::SetUp();
    fs::create_directories(dir_ / "out");
    write("plane.obj",
          "v -2 -2 0\nv 2 -2 0\nv 2 2 0\nv -2 2 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 "
          "4/4\n");
    // Tables far larger than the defaults: building them takes many seconds.
    write(
        "big.toml",
        "[camera]\nposition = [0, -3, 2]\nresolution = [160, 90]\nspp = 1\n[[lights]]\n"
        "direction = [0, 0, -1]\n[[materials]]\nname = \"m\"\n  [[materials.relief]]\n"
        "  noise = { octaves = 4 }\n  amplitude = 0.02\n  scale = 4.0\n[[objects]]\n"
        "mesh = \"plane.obj\"\nscheme = \"bilinear\"\nmaterial = \"m\"\n[render]\ncache_dir = \"" +
            (dir_ / "cache").string() +
            "\"\n[render.tables]\nrays_per_view = 65536\nmesh_resolution = 512\n");
  }

  // Starts meso, waits `after`, sends `sig`; returns the seconds from the signal to the exit and
  // the exit status in *status (-1: killed or still running after 10 s).
  double stopAfter(const std::vector<std::string>& args, std::chrono::milliseconds after, int sig,
                   int* status) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, (dir_ / "stderr.txt").c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
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
    pid_t pid;
    const int spawned = posix_spawn(&pid, MESO_EXE, &actions, &attr, argv.data(), environ);
    posix_spawnattr_destroy(&attr);
    posix_spawn_file_actions_destroy(&actions);
    *status = -1;
    if (spawned != 0) return -1.0;
    // `after` counts from when meso catches the signal: loading its libraries alone takes 0.4 s
    // here, more on a loaded machine, and a signal before the handler kills it outright.
    const auto ready = Clock::now();
    while (!catches(pid, sig) && Clock::now() - ready < std::chrono::seconds(20))
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    std::this_thread::sleep_for(after);
    int raw = 0;
    if (::waitpid(pid, &raw, WNOHANG) == pid) {
      ADD_FAILURE() << "meso ended before the signal (make the job longer): " << readErr();
      return -1.0;
    }
    const auto sent = Clock::now();
    ::kill(pid, sig);
    while (Clock::now() - sent < std::chrono::seconds(10)) {
      if (::waitpid(pid, &raw, WNOHANG) == pid) {
        *status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
        return std::chrono::duration<double>(Clock::now() - sent).count();
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &raw, 0);
    return 10.0;
  }
  // Whether process pid has a handler for sig (the SigCgt mask of /proc/pid/status).
  static bool catches(pid_t pid, int sig) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    std::string line;
    while (std::getline(in, line))
      if (line.rfind("SigCgt:", 0) == 0)
        return (std::stoull(line.substr(7), nullptr, 16) >> (sig - 1)) & 1u;
    return false;
  }
  std::string readErr() const {
    std::ifstream in(dir_ / "stderr.txt");
    return {std::istreambuf_iterator<char>(in), {}};
  }
  // No file at all under out/ (no partial output, no temporary).
  void expectNothingIn(const fs::path& folder) const {
    if (!fs::exists(folder)) return;
    for (const auto& e : fs::recursive_directory_iterator(folder))
      if (!e.is_directory()) ADD_FAILURE() << "left behind: " << e.path();
  }
  void expectStopped(const char* what, const std::vector<std::string>& args, int sig = SIGINT) {
    int status = -1;
    const double seconds = stopAfter(args, std::chrono::milliseconds(1200), sig, &status);
    std::printf("[ figure ] %s: stopped %.3f s after %s\n", what, seconds,
                sig == SIGINT ? "SIGINT" : "SIGTERM");
    EXPECT_EQ(status, 128 + sig) << what << ": " << readErr();
    EXPECT_LT(seconds, 0.5) << what;
    EXPECT_GE(seconds, 0.0) << what;
    expectNothingIn(dir_ / "out");
    // The table cache may hold complete tables, never a temporary.
    if (fs::exists(dir_ / "cache")) {
      for (const auto& e : fs::recursive_directory_iterator(dir_ / "cache"))
        EXPECT_NE(e.path().filename().string()[0], '.') << "temporary left behind: " << e.path();
    }
  }
};

TEST_F(InterruptCommandsTest, TablesBuilding) {
  expectStopped("tables", {"tables", (dir_ / "big.toml").string(), "-o", (dir_ / "out").string()});
}

TEST_F(InterruptCommandsTest, RenderWhileBuildingTables) {
  expectStopped("render (tables)",
                {"render", (dir_ / "big.toml").string(), "-q", "-o", (dir_ / "out/a.exr").string()},
                SIGTERM);
}

TEST_F(InterruptCommandsTest, PatchConsistency) {
  expectStopped("consistency", {"consistency", "--samples", "4000000", "--no-cache"});
}

TEST_F(InterruptCommandsTest, SceneConsistency) {
  expectStopped("consistency SCENE", {"consistency", (dir_ / "big.toml").string()});
}

TEST_F(InterruptCommandsTest, Bands) {
  const int w = 2048;
  std::string pixels(static_cast<size_t>(w) * w, '\0');
  std::mt19937 rng(1);
  for (char& c : pixels) c = static_cast<char>(rng() & 0xff);
  std::ofstream(dir_ / "h.pgm", std::ios::binary) << "P5\n" << w << " " << w << "\n255\n" << pixels;
  expectStopped("bands",
                {"bands", (dir_ / "h.pgm").string(), "-n", "8", "-o", (dir_ / "out").string()});
}

TEST_F(InterruptCommandsTest, Tessellation) {
  // Small tables (built in a moment), then displaced micropolygons at 0.05 px: seconds of dicing.
  write(
      "flat.toml",
      "[camera]\nposition = [0, -0.3, 0.15]\nlook_at = [0, 0.5, 0]\nresolution = [160, 90]\n"
      "spp = 1\n[[lights]]\n"
      "direction = [0, 0, -1]\n[[materials]]\nname = \"m\"\n  [[materials.relief]]\n"
      "  noise = { octaves = 8 }\n  amplitude = 0.02\n  scale = 64.0\n[[objects]]\n"
      "mesh = \"plane.obj\"\nscheme = \"catmull-clark\"\nmaterial = \"m\"\n[render]\ncache_dir = "
      "\"" +
          (dir_ / "cache").string() +
          "\"\n[render.tables]\ntheta_v_bins = 4\ntheta_n_bins = 16\n"
          "phi_bins = 8\nazimuths = 4\nrays_per_view = 64\nmesh_resolution = 16\nbrdf_theta_l = 4\n"
          "brdf_phi = 4\n");
  expectStopped("render (tessellation)",
                {"render", (dir_ / "flat.toml").string(), "-q", "-o", (dir_ / "out/a.exr").string(),
                 "--algorithm", "displacement", "--dicing-rate", "0.05"});
}

}  // namespace
