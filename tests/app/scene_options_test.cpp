// `--set KEY=VALUE` as a user meets it (src/app/scene_options.cpp): scene keys set on every command
// that reads a scene, checked like the file, errors naming --set and the key with exit status 2.
#include "support/run_meso.h"
#include "support/temp_dir.h"

#include "meso/core/image_io.h"
#include "meso/render/film_layout.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

namespace meso {
namespace {

namespace fs = std::filesystem;

using testing::RunResult;
RunResult run(const std::string& args) { return testing::runMeso(args); }

class SetOptionTest : public testing::TempDirTest {
 protected:
  void SetUp() override {
    testing::TempDirTest::SetUp();
    write("quad.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
    scene_ = write("scene.toml",
                   "[camera]\nposition = [0.4, -2.5, 2]\nup = [0, 0, 1]\nresolution = [40, 24]\n"
                   "spp = 2\n[[lights]]\ndirection = [0.3, 0.2, -1]\n[[materials]]\nname = "
                   "\"m\"\nka = 0.05\nkd = 0.6\nks = 0.3\n[[objects]]\nmesh = \"quad.obj\"\n"
                   "scheme = \"bilinear\"\nmaterial = \"m\"\n");
  }
  fs::path out(const std::string& name) const { return dir_ / "out" / name; }
  RunResult render(const std::string& exr, const std::string& args) {
    return run("render -q " + args + " -o " + out(exr).string() + " " + scene_.string());
  }
  fs::path scene_;
};

// Repeated --set before the scene; the image has the set size, and with kd and ks at 0 only the
// ambient ka = 0.05 is left in every lit pixel.
TEST_F(SetOptionTest, RenderTakesEveryKey) {
  const RunResult r = render("ambient.exr",
                             "--set camera.resolution=[20,10] --set 'materials[0].kd=0' "
                             "--set 'materials[0].ks = 0' --set render.algorithm=brdf");
  ASSERT_EQ(r.status, 0) << r.output;
  const Image film = FilmLayout::fromExr(readImage(out("ambient.exr")), "ambient.exr");
  ASSERT_EQ(film.width, 20);
  ASSERT_EQ(film.height, 10);
  float brightest = 0.0f;
  for (int y = 0; y < film.height; ++y)
    for (int x = 0; x < film.width; ++x)
      brightest = std::max(brightest, film.at(x, y, FilmLayout::R));
  EXPECT_NEAR(brightest, 0.05f, 1e-6f);
}

TEST_F(SetOptionTest, BadKeysAndValuesExitWithStatusTwoNamingTheKey) {
  const struct {
    const char* set;
    const char* message;
  } cases[] = {
      {"camera.fov=200", "meso: --set: camera.fov: expected a number in (0, 180), got 200"},
      {"render.D=x1", "meso: --set: render.D: expected a number, got a string"},
      {"render.dee=3", "meso: --set: render.dee: unknown key (allowed here: "},
      {"'materials[1].kd=0'", "meso: --set: materials: expected an index below 1"},
      {"camera.fov", "meso: --set: expected KEY=VALUE"},
      {"=3", "meso: --set: expected KEY=VALUE"},
      {"camera.fov=[1,", "meso: --set: camera.fov: expected a TOML value"},
  };
  for (const auto& c : cases) {
    const RunResult r = render("bad.exr", std::string("--set ") + c.set);
    EXPECT_EQ(r.status, 2) << c.set << ": " << r.output;
    EXPECT_EQ(r.output.rfind(c.message, 0), 0) << c.set << ": " << r.output;
    EXPECT_FALSE(fs::exists(out("bad.exr"))) << c.set;
  }
}

// consistency SCENE, tables and trade read the scene through the same path.
TEST_F(SetOptionTest, OtherCommandsThatReadAScene) {
  const std::string bad = " --set render.D=-1 ";
  const std::string expected = "meso: --set: render.D: expected a number in [0, 1e+06], got -1";
  for (const std::string& command :
       {"consistency " + scene_.string() + bad, "tables " + scene_.string() + bad + "--no-plots",
        "trade " + scene_.string() + bad + "-q -o " + (dir_ / "trade").string()}) {
    const RunResult r = run(command);
    EXPECT_EQ(r.status, 2) << command << ": " << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << command << ": " << r.output;
  }
  const RunResult patch = run("consistency --set render.D=1");
  EXPECT_EQ(patch.status, 2) << patch.output;
  EXPECT_NE(patch.output.find("--set: expected a SCENE"), std::string::npos) << patch.output;
  const RunResult tables = run("tables " + scene_.string() + " --no-plots --set render.D=3");
  EXPECT_EQ(tables.status, 0) << tables.output;
}

}  // namespace
}  // namespace meso
