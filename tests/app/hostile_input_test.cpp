// The meso executable against hostile inputs and a hostile machine (issue 18): no shell injection
// through --video, outputs that are special files refused (exit 2, the path named), inputs that are
// not regular files refused without blocking, strict option values, and a full disk that leaves no
// output of the failed frame under a final name.
#include "support/temp_dir.h"

#include "meso/core/huge_pages.h"
#include "meso/core/image_io.h"

#include <gtest/gtest.h>

#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;

struct RunResult {
  int status = -1;
  std::string output;
  double seconds = 0.0;
};

// Runs meso through the shell with `env` (variable assignments) in its environment, killed after
// 20 s.
RunResult run(const std::string& args, const std::string& env = "") {
  const std::string cmd =
      "timeout -s KILL 20 env " + env + " " + std::string(MESO_EXE) + " " + args + " 2>&1";
  RunResult r;
  const auto start = std::chrono::steady_clock::now();
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  const int raw = pclose(p);
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

std::string quoted(const fs::path& p) {
  std::string s = "'";
  for (char c : p.string()) s += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return s + "'";
}

// Files under `dir` (recursively), temporaries included.
int filesUnder(const fs::path& dir) {
  int n = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (!e.is_directory()) ++n;
  return n;
}

class HostileTest : public meso::testing::TempDirTest {
 protected:
  void SetUp() override {
    meso::testing::TempDirTest::SetUp();
    fs::create_directories(dir_ / "out");
    write("quad.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
    write("scene.toml", scene());
  }
  std::string scene(const std::string& extra = "") const {
    return "[camera]\nposition = [0, 0, 3]\nresolution = [32, 18]\nspp = 1\n[[lights]]\ndirection "
           "= [0, 0, -1]\n"
           "[[objects]]\nmesh = \"quad.obj\"\nscheme = \"bilinear\"\n" +
           extra;
  }
  // A relief (two octaves of noise) on the quad, with small tables cached under the test folder.
  std::string reliefScene() const {
    return "[[materials]]\nname = \"m\"\n  [[materials.relief]]\n  noise = { octaves = 2 }\n"
           "  amplitude = 0.01\n  scale = 4.0\n" +
           scene("material = \"m\"\n") + "[render]\ncache_dir = \"" + (dir_ / "cache").string() +
           "\"\n[render.tables]\n"
           "theta_v_bins = 4\ntheta_n_bins = 16\nphi_bins = 8\nazimuths = 4\nrays_per_view = "
           "64\nmesh_resolution = 16\nbrdf_theta_l = 4\nbrdf_phi = 4\n";
  }
  std::string path3() const {
    return scene() +
           "[path]\nframes = 3\n[[path.keys]]\ntime = 0\nposition = [0, 0, 3]\n[[path.keys]]\n"
           "time = 1\nposition = [0, 0.2, 3]\n";
  }
  std::string render(const fs::path& out, const std::string& extra = "") const {
    return "render " + quoted(dir_ / "scene.toml") + " -q -o " + quoted(out) + " " + extra;
  }
  // Mounts a tmpfs of `bytes` at dir_/name; false when this process cannot mount (not root).
  bool mountTmpfs(const std::string& name, long bytes) {
    const fs::path at = dir_ / name;
    fs::create_directories(at);
    const std::string options = "size=" + std::to_string(bytes);
    if (::mount("tmpfs", at.c_str(), "tmpfs", 0, options.c_str()) != 0) return false;
    mounts_.push_back(at);
    return true;
  }
  void TearDown() override {
    for (const fs::path& m : mounts_) ::umount2(m.c_str(), MNT_DETACH);
    meso::testing::TempDirTest::TearDown();
  }
  std::vector<fs::path> mounts_;
};

// A quote in the --video name used to end the shell's string and run $(...): ffmpeg now runs from
// an argument vector, and the name is only a name.
TEST_F(HostileTest, VideoNameIsNeverShellCode) {
  write("scene.toml", path3());
  const fs::path marker = dir_ / "PWNED";
  const fs::path video =
      dir_ / ("v'; touch " + marker.string() + "; echo '$(touch " + marker.string() + ").mp4");
  const RunResult r = run(render(dir_ / "out/f.exr", "--video " + quoted(video)));
  EXPECT_FALSE(fs::exists(marker)) << r.output;
  if (r.status == 0) {
    EXPECT_TRUE(fs::exists(video)) << r.output;
  }
  EXPECT_NE(r.status, 130) << r.output;
}

// A still has no frames to assemble: refused before rendering (ffmpeg used to fail after it). Odd
// frame sizes are padded for the encoder (libx264 refused them after every frame was rendered).
TEST_F(HostileTest, VideoOfAStillIsRefusedAndOddSizesAreEncoded) {
  RunResult r = run(render(dir_ / "out/f.exr", "--video " + quoted(dir_ / "v.mp4")));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("v.mp4: --video: expected a scene with a [path]"), std::string::npos)
      << r.output;
  EXPECT_EQ(filesUnder(dir_ / "out"), 0);
  std::string odd = path3();
  odd.replace(odd.find("[32, 18]"), 8, "[33, 19]");
  write("scene.toml", odd);
  if (std::system("command -v ffmpeg >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "ffmpeg is not installed: the odd-size video is not tried";
  r = run(render(dir_ / "out/f.exr", "--video " + quoted(dir_ / "v.mp4")));
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_GT(fs::file_size(dir_ / "v.mp4"), 0u);
}

// Without ffmpeg the run stops before rendering anything (it used to render every frame first).
TEST_F(HostileTest, VideoWithoutFfmpegFailsBeforeRendering) {
  write("scene.toml", path3());
  const RunResult r =
      run(render(dir_ / "out/f.exr", "--video " + quoted(dir_ / "v.mp4")), "PATH=/nonexistent");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("v.mp4: --video: expected ffmpeg on the PATH"), std::string::npos)
      << r.output;
  EXPECT_EQ(filesUnder(dir_ / "out"), 0);
}

// Outputs that exist and are not regular files are refused (and left as they were); outputs in a
// folder that is a file, or onto a folder, are bad input too: exit 2 naming the path.
TEST_F(HostileTest, SpecialOutputsAreRefusedWithStatusTwo) {
  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0644), 0);
  fs::create_symlink(dir_ / "target.json", dir_ / "link.json");
  fs::create_directories(dir_ / "folder.exr");
  write("file.txt", "x");
  struct Case {
    std::string args, expected;
  };
  const Case cases[] = {
      {render(dir_ / "out/a.exr", "--stats /dev/null"),
       "/dev/null: --stats: expected a regular file to write (or no file), found a character "
       "device"},
      {render(dir_ / "out/a.exr", "--stats " + quoted(dir_ / "fifo")),
       "fifo: --stats: expected a regular file to write (or no file), found a FIFO"},
      {render(dir_ / "out/a.exr", "--stats " + quoted(dir_ / "link.json")),
       "link.json: --stats: expected a regular file to write (or no file), found a symbolic link"},
      {render(dir_ / "out/a.exr", "--stats " + quoted(dir_ / "out")),
       "out: --stats: expected a regular file to write (or no file), found a folder"},
      {render(dir_ / "folder.exr"),
       "folder.exr: -o: expected a regular file to write (or no file), found a folder"},
      {render(dir_ / "file.txt/a.exr"), "a.exr: -o: expected a folder to write into, " +
                                            (dir_ / "file.txt").string() + " is a file"},
      {render(dir_ / "out/a.exr", "--stats " + quoted(dir_ / "file.txt/s.json")),
       "s.json: --stats: expected a folder to write into"},
      {"tables " + quoted(dir_ / "scene.toml") + " -o /proc/x",
       "/proc/x: -o: cannot create the folder"},
      // A folder that takes no new files (even for root) is refused before rendering.
      {render("/proc/a.exr"), "/proc/a.exr: -o: cannot write into the folder /proc"},
      {"tables " + quoted(dir_ / "scene.toml") + " -o " + quoted(dir_ / "file.txt"),
       "file.txt: -o: expected a folder"},
  };
  for (const Case& c : cases) {
    const RunResult r = run(c.args);
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos)
        << c.args << ": expected \"" << c.expected << "\" in\n"
        << r.output;
    EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
  }
  struct stat st;
  ASSERT_EQ(::stat("/dev/null", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode)) << "/dev/null was replaced";
  EXPECT_TRUE(fs::is_fifo(dir_ / "fifo"));
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.json"));
  EXPECT_FALSE(fs::exists(dir_ / "target.json"));
  EXPECT_EQ(filesUnder(dir_ / "out"), 0);
}

TEST_F(HostileTest, BandsOutputOntoAFileIsStatusTwo) {
  // An 8 x 8 PGM height image (two bands of an octave).
  std::ofstream(dir_ / "h.pgm", std::ios::binary) << "P5\n8 8\n255\n" << std::string(64, '\x40');
  write("file.txt", "x");
  const RunResult r =
      run("bands " + quoted(dir_ / "h.pgm") + " -n 2 -o " + quoted(dir_ / "file.txt"));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("file.txt: -o: expected a folder"), std::string::npos) << r.output;
}

// A FIFO as the scene used to block forever and /dev/zero to read 4 GB.
TEST_F(HostileTest, SpecialInputsAreRefusedWithoutBlocking) {
  ASSERT_EQ(::mkfifo((dir_ / "fifo.toml").c_str(), 0644), 0);
  ASSERT_EQ(::mkfifo((dir_ / "fifo.obj").c_str(), 0644), 0);
  ASSERT_EQ(::mkfifo((dir_ / "fifo.png").c_str(), 0644), 0);
  struct Case {
    std::string args, expected;
  };
  write("mesh-fifo.toml", scene().replace(scene().find("quad.obj"), 8, "fifo.obj"));
  const Case cases[] = {
      {"render " + quoted(dir_ / "fifo.toml") + " -q -o " + quoted(dir_ / "out/a.exr"),
       "fifo.toml: scene: expected a regular file, found a FIFO"},
      {"render /dev/zero -q -o " + quoted(dir_ / "out/a.exr"),
       "/dev/zero: scene: expected a regular file, found a character device"},
      {"tables " + quoted(dir_ / "fifo.toml") + " --no-plots",
       "fifo.toml: scene: expected a regular file, found a FIFO"},
      {"render " + quoted(dir_ / "mesh-fifo.toml") + " -q -o " + quoted(dir_ / "out/a.exr"),
       "objects.mesh: not a regular file"},
      {"bands " + quoted(dir_ / "fifo.png") + " -o " + quoted(dir_ / "out"),
       "fifo.png: image: expected a regular file, found a FIFO"},
      {"consistency --height /dev/zero --theta-v 0",
       "/dev/zero: image: expected a regular file, found a character device"},
  };
  for (const Case& c : cases) {
    const RunResult r = run(c.args);
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.output;
    EXPECT_LT(r.seconds, 5.0) << c.args;
    EXPECT_NE(r.output.find(c.expected), std::string::npos)
        << c.args << ": expected \"" << c.expected << "\" in\n"
        << r.output;
  }
  EXPECT_EQ(filesUnder(dir_ / "out"), 0);
}

// Option values: trailing junk and non-finite numbers are errors naming the option.
TEST_F(HostileTest, OptionValuesAreStrict) {
  write("scene.toml", path3());
  struct Case {
    std::string args, expected;
  };
  const Case cases[] = {
      {render(dir_ / "out/a.exr", "--dicing-rate nan"),
       "--dicing-rate: expected a finite number, got \"nan\""},
      {render(dir_ / "out/a.exr", "--D inf"), "--D: "},
      {render(dir_ / "out/a.exr", "--thresholds=-2,-1,nan,2"),
       "--thresholds: expected a finite number, got \"nan\""},
      {render(dir_ / "out/a.exr", "--frames 1x:2y"),
       "--frames: expected A, A: or A:B with 0 <= A <= B < 3, got \"1x:2y\""},
      {render(dir_ / "out/a.exr", "--frames 0:79:8"), "got \"0:79:8\" (a step is not supported)"},
      {render(dir_ / "out/a.exr", "--frames 2:1"), "--frames: expected A, A: or A:B"},
      {render(dir_ / "out/a.exr", "--shard 1/2x"),
       "--shard: expected i/n with 0 <= i < n, got \"1/2x\""},
      {"consistency --normalize nan", "--normalize: expected a finite number, got \"nan\""},
      {"consistency --theta-v 10,nan", "--theta-v: expected a finite number, got \"nan\""},
      {"consistency --theta-v 30,90", "--theta-v: expected angles in [0, 90) degrees"},
      // Unsigned options used to wrap "-1" to 2^64 - 1 and saturate larger numbers silently.
      {render(dir_ / "out/a.exr", "--seed -1"),
       "--seed: expected a whole number of 0 or more, got \"-1\""},
      {render(dir_ / "out/a.exr", "--seed 99999999999999999999999"),
       "--seed: expected a whole number below 2^64"},
      {"consistency --seed -5", "--seed: expected a whole number of 0 or more, got \"-5\""},
      {"consistency --component shiny", "--component: shiny not in {diffuse,specular,both}"},
      {"consistency --format html", "--format: html not in {csv,markdown}"},
      {render(dir_ / "out/a.exr", "--dicing-metric screen"),
       "--dicing-metric: screen not in {isotropic,projected}"},
      {"trade " + quoted(dir_ / "scene.toml") + " --band nan",
       "--band: expected a finite number, got \"nan\""},
      {"trade " + quoted(dir_ / "scene.toml") + " --frames 0:1:1", "(a step is not supported)"},
      // An empty path used to be taken for the default (out/<scene name>.exr).
      {"render " + quoted(dir_ / "scene.toml") + " -q -o ''",
       "--output: expected a value, got an empty string"},
      {render(dir_ / "out/a.exr", "--stats ''"), "--stats: expected a value, got an empty string"},
      {"consistency --cache-dir ''", "--cache-dir: expected a value, got an empty string"},
  };
  for (const Case& c : cases) {
    const RunResult r = run(c.args);
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos)
        << c.args << ": expected \"" << c.expected << "\" in\n"
        << r.output;
  }
  EXPECT_EQ(filesUnder(dir_ / "out"), 0);
}

// A full disk: the frame's EXR and PNG do not appear (half a PNG used to be left, exit 0).
TEST_F(HostileTest, FullDiskLeavesNoPartialOutput) {
  if (!mountTmpfs("full", 4096))
    GTEST_SKIP() << "cannot mount a tmpfs here (needs root): the write hook test in "
                    "core/atomic_file_test covers the same path";
  const RunResult r = run(render(dir_ / "full/a.exr"));
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("No space left on device"), std::string::npos) << r.output;
  EXPECT_EQ(filesUnder(dir_ / "full"), 0);
}

// The stats cannot be written: the frame's EXR and PNG are not left under their final names.
TEST_F(HostileTest, FailedStatsWriteLeavesNoFrame) {
  if (!mountTmpfs("full", 4096)) GTEST_SKIP() << "cannot mount a tmpfs here (needs root)";
  std::ofstream(dir_ / "full/filler", std::ios::binary) << std::string(4096, 'x');
  const RunResult r =
      run(render(dir_ / "out/a.exr", "--stats " + quoted(dir_ / "full/stats.json")));
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("full/stats.json: cannot write: No space left on device"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(filesUnder(dir_ / "out"), 0);
  EXPECT_EQ(filesUnder(dir_ / "full"), 1);  // the filler
}

// Mesh problems found after reading name the mesh file; relief on a mesh without vt warns.
TEST_F(HostileTest, MeshProblemsNameTheFile) {
  write("loop.toml", scene().replace(scene().find("bilinear"), 8, "loop"));
  RunResult r =
      run("render " + quoted(dir_ / "loop.toml") + " -q -o " + quoted(dir_ / "out/a.exr"));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(
      r.output.find((dir_ / "quad.obj").string() + ": Loop subdivision needs an all-triangle mesh"),
      std::string::npos)
      << r.output;
  std::string gon;
  for (int i = 0; i < 100000; ++i)
    gon.append("v ")
        .append(std::to_string(std::cos(i * 6.283185307 / 100000)))
        .append(" ")
        .append(std::to_string(std::sin(i * 6.283185307 / 100000)))
        .append(" 0\n");
  gon += "f";
  for (int i = 1; i <= 100000; ++i) gon.append(" ").append(std::to_string(i));
  write("gon.obj", gon + "\n");
  write("gon.toml", scene().replace(scene().find("quad.obj"), 8, "gon.obj"));
  r = run("render " + quoted(dir_ / "gon.toml") + " -q -o " + quoted(dir_ / "out/a.exr"));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(
      r.output.find((dir_ / "gon.obj").string() + ": control mesh face 0 has 100000 vertices"),
      std::string::npos)
      << r.output;
  EXPECT_EQ(filesUnder(dir_ / "out"), 0);
  write("relief.toml", reliefScene());
  r = run("render " + quoted(dir_ / "relief.toml") + " -q -o " + quoted(dir_ / "out/a.exr"));
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("quad.obj: the mesh has no texture coordinates (vt)"), std::string::npos)
      << r.output;
}

// Jobs whose estimated memory exceeds --memory-limit are refused before allocating, naming the key
// and the estimate; the micropolygon cap is lowered to what fits.
TEST_F(HostileTest, MemoryIsEstimatedBeforeAllocating) {
  // 69 bytes of PNG declaring a 60000 x 60000 grey image (13 GiB as float).
  const std::string png(
      "\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\xea\x60\x00\x00\xea"
      "\x60\x08"
      "\x00\x00\x00\x00\xa5\xb9\x2a\x9e\x00\x00\x00\x0c\x49\x44\x41\x54\x78\x9c\x63\x60\xa0\x3d\x00"
      "\x00\x00"
      "\x64\x00\x01\x86\x64\x3c\x35\x00\x00\x00\x00\x49\x45\x4e\x44\xae\x42\x60\x82",
      69);
  std::ofstream(dir_ / "huge.png", std::ios::binary) << png;
  RunResult r = run("bands " + quoted(dir_ / "huge.png") + " -o " + quoted(dir_ / "out"));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(
      r.output.find(
          "huge.png: truncated or corrupt PNG: 69 bytes cannot hold the 60000x60000 pixels its "
          "header declares"),
      std::string::npos)
      << r.output;
  EXPECT_LT(r.seconds, 5.0);
  // A PNG that could hold them (padded to 4 MB) is refused by the memory estimate instead.
  std::ofstream(dir_ / "padded.png", std::ios::binary)
      << png.substr(0, 33) << std::string("\x00\x40\x00\x00tEXt", 8) << std::string(0x400000, 'x')
      << std::string("\x00\x00\x00\x00", 4) << png.substr(33);
  r = run("bands " + quoted(dir_ / "padded.png") + " -o " + quoted(dir_ / "out") +
          " --memory-limit 4096");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(
      r.output.find(
          "padded.png: image: needs an estimated 17166.1 MiB (decoding 60000x60000, 1 channels, as "
          "the header declares), more than the memory limit of 4096.0 MiB"),
      std::string::npos)
      << r.output;
  EXPECT_LT(r.seconds, 5.0);

  r = run(render(dir_ / "out/a.exr", "--width 16384 --height 16384 --memory-limit 4096"));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(
      r.output.find(
          "scene.toml: camera.resolution: needs an estimated 24064.0 MiB (the film of 16384x16384"),
      std::string::npos)
      << r.output;

  write("tables.toml",
        "[[materials]]\nname = \"m\"\n  [[materials.relief]]\n  noise = {}\n" +
            scene("material = \"m\"\n") +
            "[render.tables]\ntheta_v_bins = 90\nphi_v_bins = 64\ntheta_n_bins = 1024\n"
            "phi_bins = 1024\n");
  for (const std::string& command :
       {"render " + quoted(dir_ / "tables.toml") + " -q -o " + quoted(dir_ / "out/a.exr"),
        "tables " + quoted(dir_ / "tables.toml") + " --no-plots"}) {
    r = run(command);
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("tables.toml: render.tables.theta_n_bins/phi_bins: needs an estimated"),
              std::string::npos)
        << r.output;
    EXPECT_LT(r.seconds, 5.0);
  }

  write("relief.toml", reliefScene());
  r = run("render " + quoted(dir_ / "relief.toml") + " -q -o " + quoted(dir_ / "out/a.exr") +
          " --algorithm displacement --memory-limit 128");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("render.max_micropolygons: lowered from 80000000 to "), std::string::npos)
      << r.output;

  // The control mesh counts too: its limit surface (about 140 bytes a face) and, displaced, its
  // dicing (560): a grid of 40 000 faces needs about 27 MiB before any micropolygon, and meso
  // render holds what its process measures once the mesh is read where that is more (about 55 MiB
  // here: the libraries' own heap, and what reading the mesh left in it).
  // An n x n grid over [-1, 1]^2, its heights `amplitude` sin(i / 10) cos(j / 13).
  const auto gridObj = [](int n, double amplitude) {
    std::string obj;
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        obj += "v " + std::to_string(2.0 * i / n - 1) + " " + std::to_string(2.0 * j / n - 1) +
               " " + std::to_string(amplitude * std::sin(i / 10.0) * std::cos(j / 13.0)) + "\n";
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int a = j * (n + 1) + i + 1;
        obj += "f " + std::to_string(a) + " " + std::to_string(a + 1) + " " +
               std::to_string(a + n + 2) + " " + std::to_string(a + n + 1) + "\n";
      }
    return obj;
  };
  const std::string scene = reliefScene();
  const auto writeMesh = [&](const std::string& name, const std::string& obj) {
    write(name + ".obj", obj);
    std::string s = scene;
    s.replace(s.find("quad.obj"), 8, name + ".obj");
    write(name + ".toml", s);
  };
  writeMesh("grid", gridObj(200, 0.0));
  r = run("render " + quoted(dir_ / "grid.toml") + " -q -o " + quoted(dir_ / "out/g.exr") +
          " --algorithm displacement --memory-limit 16");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find((dir_ / "grid.obj").string() + ": mesh: needs an estimated "),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("the limit surfaces of 40000 control faces"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "out/g.exr"));
  // 40 MiB holds the estimate of a flat grid of 22 500 faces under bump (two triangles a face:
  // about 10 MiB) but not the process as measured: refused, naming it.
  writeMesh("small", gridObj(150, 0.0));
  if (meso::kHugeNewBuilt) {
    r = run("render " + quoted(dir_ / "small.toml") + " -q -o " + quoted(dir_ / "out/g.exr") +
            " --algorithm bump --memory-limit 40");
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("needs an estimated "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("the process so far "), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "out/g.exr"));
  }
  r = run("render " + quoted(dir_ / "small.toml") + " -q -o " + quoted(dir_ / "out/g.exr") +
          " --algorithm displacement --memory-limit 128");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("the limit surfaces of 22500 control faces"), std::string::npos)
      << r.output;
  // The measured process (not under AddressSanitizer, whose own memory it would be).
  if (meso::kHugeNewBuilt) {
    EXPECT_NE(r.output.find("(--memory-limit) beside the process so far "), std::string::npos)
        << r.output;
  }

  // A curved grid is tessellated per frame by every renderer; its dicing holds 560 bytes a face
  // where it is displaced, 150 where nothing is: 90 000 faces need 48.1 and 12.9 MiB for it, and
  // about 25 MiB in all at the least, more than the smallest limit (16 MiB).
  writeMesh("hills", gridObj(300, 0.05));
  for (const auto& [algorithm, dicing] :
       {std::pair("displacement", "their dicing 48.1 MiB"),
        std::pair("bump", "their dicing 12.9 MiB"), std::pair("brdf", "their dicing 12.9 MiB")}) {
    r = run("render " + quoted(dir_ / "hills.toml") + " -q -o " + quoted(dir_ / "out/h.exr") +
            " --algorithm " + algorithm + " --memory-limit 16");
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find(dicing), std::string::npos) << algorithm << ": " << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "out/h.exr"));
  }
}

// --memory-limit reaches every image a scene reads: a height image (read when the scene is loaded,
// to plan its bands), a colour texture and an environment map (read when the tables are prepared)
// are refused before decoding when their declared size exceeds it, and read under a larger limit.
TEST_F(HostileTest, MemoryLimitReachesEveryImageAScenesReads) {
  meso::Image big(2048, 2048, {"Y"});  // 32 MiB decoded as a height, 112 MiB as a colour texture
  for (float& v : big.pixels) v = 0.5f;
  meso::writeExr(dir_ / "big.exr", big);
  const std::string cache = "[render]\ncache_dir = \"" + (dir_ / "cache").string() + "\"\n";
  const std::string relief =
      "[[materials]]\nname = \"m\"\n  [[materials.relief]]\n  height = \"big.exr\"\n"
      "  amplitude = 0.01\n";
  const std::string kd = "[[materials]]\nname = \"m\"\nkd = \"big.exr\"\n";
  const std::string environment = "[[lights]]\ntype = \"environment\"\nenvironment = \"big.exr\"\n";
  const struct {
    std::string toml, message;
  } cases[] = {
      {relief + scene("material = \"m\"\n") + cache,
       "big.exr: image: needs an estimated 32.0 MiB (decoding 2048x2048, 1 channels"},
      {kd + scene("material = \"m\"\n") + cache,
       "big.exr: colour textures: needs an estimated 112.0 MiB"},
      {environment + scene() + cache, "big.exr: environment maps: needs an estimated 112.0 MiB"},
  };
  for (const auto& c : cases) {
    write("images.toml", c.toml);
    const std::string command =
        "render " + quoted(dir_ / "images.toml") + " -q -o " + quoted(dir_ / "out/i.exr");
    RunResult r = run(command + " --memory-limit 16");
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("more than the memory limit of 16.0 MiB"), std::string::npos)
        << r.output;
    if (c.message.find("image:") != std::string::npos) continue;  // relief: tables too large
    r = run(command + " --memory-limit 512");
    EXPECT_EQ(r.status, 0) << r.output;
  }
}

}  // namespace
