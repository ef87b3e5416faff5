// The meso executable as a user meets it: exit status, messages and output files, for good and bad
// input. Each bad input must give status 2, a message naming FILE[:LINE:COL]: key, and no output.
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

struct RunResult {
  int status = -1;
  std::string output;  // stdout and stderr
};

RunResult run(const std::string& args) {
  const std::string cmd = std::string(MESO_EXE) + " " + args + " 2>&1";
  RunResult r;
  FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  const int raw = pclose(p);
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return r;
}

class CliTest : public meso::testing::TempDirTest {
 protected:
  void SetUp() override {
    meso::testing::TempDirTest::SetUp();
    std::filesystem::create_directories(dir_ / "out");
    write("quad.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
  }
  std::string scene(const std::string& extra, const std::string& mesh = "quad.obj") {
    return "[camera]\nposition = [0, 0, 3]\nresolution = [32, 18]\nspp = 1\n[[lights]]\ndirection = [0, 0, -1]\n"
           "[[objects]]\nmesh = \"" + mesh + "\"\nscheme = \"bilinear\"\n" + extra;
  }
  bool outputFolderEmpty() const { return fs::is_empty(dir_ / "out"); }
  RunResult render(const std::string& sceneText, const std::string& extraArgs = "") {
    write("scene.toml", sceneText);
    return run("render " + (dir_ / "scene.toml").string() + " -o " + (dir_ / "out/img.exr").string() + " -q " + extraArgs);
  }
};

TEST_F(CliTest, ValidSceneWritesExrPngAndStats) {
  const RunResult r = render(scene(""), "--stats " + (dir_ / "out/stats.json").string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir_ / "out/img.exr"));
  EXPECT_TRUE(fs::exists(dir_ / "out/img.png"));
  std::ifstream in(dir_ / "out/stats.json");
  std::stringstream s;
  s << in.rdbuf();
  for (const char* key : {"\"seconds\"", "\"parse\"", "\"tessellate\"", "\"bvh\"", "\"render\"", "\"write\"", "\"total\"",
                          "\"peak_rss_mib\"", "\"rays\"", "\"triangles\"", "\"settings\""})
    EXPECT_NE(s.str().find(key), std::string::npos) << key;
  EXPECT_NE(s.str().find("\"rays\": 576"), std::string::npos) << s.str();  // 32 x 18 x 1
}

struct BadInput {
  const char* name;
  std::string sceneExtra;  // appended to a valid scene
  std::string expected;    // substring of the message; {S} stands for the scene file's path
};

TEST_F(CliTest, BadScenesExitWithStatusTwoAndNoOutput) {
  write("empty.obj", "");
  write("nofaces.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  write("garbage.obj", "\x01\x02 this is not an obj \xff\n f 9 9 9\n");
  write("mesh.stl", "solid x\nendsolid x\n");
  const BadInput cases[] = {
      {"unknown key", "colour = 3\n", "{S}:10:1: objects.colour: unknown key"},
      {"wrong type", "material = 4\n", "{S}:10:12: objects.material: expected a string, got 4"},
      {"nan", "[render]\nD = nan\n", "{S}:11:5: render.D: expected a finite number"},
      {"inf", "[render]\neps = -inf\n", "{S}:11:7: render.eps: expected a finite number"},
      {"out of range", "[render]\nthreads = 5000\n", "{S}:11:11: render.threads: expected an integer in [0, 1024], got 5000"},
      {"bad enum", "[render]\nalgorithm = \"fast\"\n", "{S}:11:13: render.algorithm: expected one of auto"},
      {"malformed toml", "[render\n", "{S}:10:"},
      {"thresholds order", "[render]\nthresholds = [1, -0.3, 0.3, 1]\n", "{S}:11:14: render.thresholds:"},
      {"missing mesh", "[[objects]]\nmesh = \"absent.obj\"\n", "{S}:11:8: objects.mesh: file not found:"},
      {"mesh is a folder", "[[objects]]\nmesh = \"out\"\n", "{S}:11:8: objects.mesh: not a regular file"},
      {"empty mesh", "[[objects]]\nmesh = \"empty.obj\"\n", "empty.obj: empty mesh file"},
      {"mesh without faces", "[[objects]]\nmesh = \"nofaces.obj\"\n", "nofaces.obj: mesh has no faces"},
      {"garbage mesh", "[[objects]]\nmesh = \"garbage.obj\"\n", "garbage.obj: "},
      {"unknown mesh format", "[[objects]]\nmesh = \"mesh.stl\"\n", "mesh.stl: unknown mesh format \".stl\""},
      {"absurd resolution", "[camera]\nresolution = [100000, 10]\n", "camera"},
  };
  const std::string scenePath = (dir_ / "scene.toml").string();
  for (const BadInput& c : cases) {
    std::string expected = c.expected;
    if (expected.rfind("{S}", 0) == 0) expected = scenePath + expected.substr(3);
    const RunResult r = render(scene(c.sceneExtra));
    EXPECT_EQ(r.status, 2) << c.name << ": " << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << c.name << ": expected \"" << expected << "\" in\n" << r.output;
    EXPECT_TRUE(outputFolderEmpty()) << c.name;
  }
}

TEST_F(CliTest, MissingSceneFileAndBadOptions) {
  RunResult r = run("render " + (dir_ / "none.toml").string() + " -o " + (dir_ / "out/x.exr").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("none.toml: cannot open scene file (No such file or directory)"), std::string::npos) << r.output;
  write("scene.toml", scene(""));
  r = run("render " + (dir_ / "scene.toml").string() + " --spp 0");
  EXPECT_EQ(r.status, 2) << r.output;
  r = run("render " + (dir_ / "scene.toml").string() + " -o " + (dir_ / "out/x.png").string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("output must be an .exr file"), std::string::npos) << r.output;
  r = run("frobnicate");
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(outputFolderEmpty());
}

}  // namespace
