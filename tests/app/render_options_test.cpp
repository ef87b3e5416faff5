// `meso render`'s options as a user meets them (src/app/render_options.cpp): --crop renders a
// window of the image bit for bit, the camera options are the scene's camera keys, a scene without
// lights and an object no frame shows are warned about, and --help gives every option's default.
#include "support/run_meso.h"
#include "support/temp_dir.h"

#include "meso/core/image_io.h"
#include "meso/render/film_layout.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

namespace meso {
namespace {

namespace fs = std::filesystem;

using testing::RunResult;
RunResult run(const std::string& args) { return testing::runMeso(args); }

class RenderOptionsTest : public testing::TempDirTest {
 protected:
  void SetUp() override {
    testing::TempDirTest::SetUp();
    fs::create_directories(dir_ / "out");
    write("quad.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
  }
  // A 40 x 24 image of a lit quad seen at an angle; `lights` replaces its one light.
  fs::path scene(const std::string& lights = "[[lights]]\ndirection = [0.3, 0.2, -1]\n") {
    return write("scene.toml",
                 "[camera]\nposition = [0.4, -2.5, 2]\nup = [0, 0, 1]\nresolution = [40, 24]\n"
                 "spp = 2\n" +
                     lights +
                     "[[materials]]\nname = \"m\"\nka = 0.05\nkd = 0.6\nks = 0.3\n[[objects]]\n"
                     "mesh = \"quad.obj\"\nscheme = \"bilinear\"\nmaterial = \"m\"\n");
  }
  RunResult render(const std::string& exr, const std::string& args) {
    return run("render " + scene().string() + " -q -o " + (dir_ / "out" / exr).string() + " " +
               args);
  }
  Image film(const std::string& exr) const {
    return FilmLayout::fromExr(readImage(dir_ / "out" / exr), exr);
  }
};

// The window's EXR is the window's size and every channel of every pixel is the whole image's bit
// for bit (samples are drawn per image pixel); the PNG is written beside it.
TEST_F(RenderOptionsTest, CropIsTheWindowOfTheWholeImage) {
  RunResult r = render("whole.exr", "");
  ASSERT_EQ(r.status, 0) << r.output;
  r = render("crop.exr", "--crop 7,3,33,20");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir_ / "out/crop.png"));
  const Image whole = film("whole.exr"), crop = film("crop.exr");
  ASSERT_EQ(crop.width, 26);
  ASSERT_EQ(crop.height, 17);
  int lit = 0;
  for (int y = 0; y < crop.height; ++y)
    for (int x = 0; x < crop.width; ++x) {
      for (int c = 0; c < FilmLayout::kChannels; ++c)
        ASSERT_EQ(crop.at(x, y, c), whole.at(7 + x, 3 + y, c))
            << FilmLayout::kNames[c] << " " << x << "," << y;
      lit += crop.at(x, y, FilmLayout::R) > 0.1f;
    }
  EXPECT_GT(lit, 50) << "the quad is in the window";
  // With --width and --height the window is checked against the new size.
  r = render("small.exr", "--width 20 --height 10 --crop 0,0,20,10");
  EXPECT_EQ(r.status, 0) << r.output;
}

TEST_F(RenderOptionsTest, BadCropsExitWithStatusTwoNamingTheOption) {
  for (const char* crop : {"0,0,41,10", "5,0,5,10", "10,0,5,10", "-1,0,5,5", "0,0,5", "0,0,5,5,5",
                           "a,0,5,5", "0,,5,5", "0,0,5,25"}) {
    const RunResult r = render("bad.exr", std::string("--crop ") + crop);
    EXPECT_EQ(r.status, 2) << crop << ": " << r.output;
    EXPECT_NE(r.output.find("--crop"), std::string::npos) << crop << ": " << r.output;
    EXPECT_TRUE(fs::is_empty(dir_ / "out")) << crop;
  }
  const RunResult r = render("bad.exr", "--crop 0,0,41,10");
  EXPECT_NE(r.output.find("0 <= X0 < X1 <= 40 and 0 <= Y0 < Y1 <= 24"), std::string::npos)
      << r.output;
}

// An object no frame shows (here behind the camera, or beside the view) is named on stderr; the
// same object moved into the view is not.
TEST_F(RenderOptionsTest, AnObjectOutsideTheViewIsWarnedAbout) {
  write("plane.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
  const auto withPlaneAt = [&](const std::string& translate) {
    std::ifstream in(scene());
    const std::string text = std::string(std::istreambuf_iterator<char>(in), {}) +
                             "[[objects]]\nmesh = \"plane.obj\"\nscheme = " +
                             "\"bilinear\"\nmaterial = \"m\"\ntranslate = " + translate + "\n";
    return write("two.toml", text);
  };
  const std::string warning = "the object plane.obj lies outside the view of the camera";
  for (const char* outside : {"[0, -6, 2]", "[30, 0, 0]"}) {
    const RunResult r = run("render " + withPlaneAt(outside).string() + " -q -o " +
                            (dir_ / "out/outside.exr").string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("two.toml:"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(warning), std::string::npos) << outside << ": " << r.output;
    EXPECT_EQ(r.output.find("quad.obj lies outside"), std::string::npos) << r.output;
  }
  const RunResult r = run("render " + withPlaneAt("[0.5, 0.5, 0]").string() + " -q -o " +
                          (dir_ / "out/inside.exr").string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.find("lies outside the view"), std::string::npos) << r.output;
}

// Without lights only the ambient term is left: said on stderr (also with -q), once; a scene with
// a light says nothing of the kind.
TEST_F(RenderOptionsTest, ASceneWithoutLightsIsWarnedAbout) {
  const std::string out = (dir_ / "out/dark.exr").string();
  RunResult r = run("render " + scene("").string() + " -q -o " + out);
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string warning = "scene.toml has no lights: the image is black except for";
  EXPECT_NE(r.output.find("meso: warning: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(warning), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find(warning), r.output.rfind(warning)) << "once";
  const Image dark = FilmLayout::fromExr(readImage(out), out);
  float brightest = 0.0f;
  for (int y = 0; y < dark.height; ++y)
    for (int x = 0; x < dark.width; ++x)
      brightest = std::max(brightest, dark.at(x, y, FilmLayout::R));
  EXPECT_NEAR(brightest, 0.05f, 1e-6f) << "ka alone";
  r = render("lit.exr", "");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.find("no lights"), std::string::npos) << r.output;
}

// --camera-position, --look-at and --fov are the scene's camera keys: the same image bit for bit as
// a file that says them.
TEST_F(RenderOptionsTest, CameraOptionsAreTheCameraKeys) {
  const std::string light = "[[lights]]\ndirection = [0.3, 0.2, -1]\n";
  RunResult r = render("moved.exr", "--camera-position -0.2,-2,2.5 --look-at 0.1,0,0 --fov 35");
  ASSERT_EQ(r.status, 0) << r.output;
  const fs::path edited =
      write("edited.toml",
            "[camera]\nposition = [-0.2, -2, 2.5]\nlook_at = [0.1, 0, 0]\nfov = 35\n"
            "up = [0, 0, 1]\nresolution = [40, 24]\nspp = 2\n" +
                light +
                "[[materials]]\nname = \"m\"\nka = 0.05\nkd = 0.6\nks = 0.3\n"
                "[[objects]]\nmesh = \"quad.obj\"\nscheme = \"bilinear\"\n"
                "material = \"m\"\n");
  r = run("render " + edited.string() + " -q -o " + (dir_ / "out/edited.exr").string());
  ASSERT_EQ(r.status, 0) << r.output;
  r = render("unmoved.exr", "");
  ASSERT_EQ(r.status, 0) << r.output;
  const Image moved = film("moved.exr"), same = film("edited.exr"), unmoved = film("unmoved.exr");
  int differs = 0;
  for (int y = 0; y < moved.height; ++y)
    for (int x = 0; x < moved.width; ++x)
      for (int c = 0; c < FilmLayout::kChannels; ++c) {
        ASSERT_EQ(moved.at(x, y, c), same.at(x, y, c)) << x << "," << y << " " << c;
        differs += moved.at(x, y, c) != unmoved.at(x, y, c);
      }
  EXPECT_GT(differs, 100) << "the options moved the camera";
}

TEST_F(RenderOptionsTest, BadCameraOptionsExitWithStatusTwoNamingTheOption) {
  const struct {
    const char* args;
    const char* message;
  } cases[] = {
      {"--fov 200", "meso: --fov: camera.fov: expected a number in (0, 180), got 200"},
      {"--fov 0", "meso: --fov: camera.fov: expected a number in (0, 180), got 0"},
      {"--fov abc", "meso: --fov: expected degrees in (0, 180), got \"abc\""},
      {"--fov nan", "meso: --fov: expected degrees in (0, 180), got \"nan\""},
      {"--camera-position 1,2", "meso: --camera-position: expected X,Y,Z (three numbers"},
      {"--camera-position 1,2,3,4", "meso: --camera-position: expected X,Y,Z (three numbers"},
      {"--look-at 1,,2", "meso: --look-at: expected X,Y,Z (three numbers"},
      {"--look-at=0.4,-2.5,2",
       "meso: --look-at: camera.look_at: expected a point different from camera.position"},
      {"--camera-position 0,0,1e300",
       "meso: --camera-position: camera.position: expected a number in [-1e+30, 1e+30], got "
       "1e+300"},
  };
  for (const auto& c : cases) {
    const RunResult r = render("bad.exr", c.args);
    EXPECT_EQ(r.status, 2) << c.args << ": " << r.output;
    EXPECT_EQ(r.output.rfind(c.message, 0), 0) << c.args << ": " << r.output;
  }
  // A [path] places the camera in its keyframes: the options are refused, --set is not.
  const fs::path path = scene(
      "[[lights]]\ndirection = [0.3, 0.2, -1]\n[path]\nframes = 2\n[[path.keys]]\ntime = 0\n"
      "[[path.keys]]\ntime = 1\nposition = [0.5, -2.5, 2]\n");
  for (const char* option : {"--fov 30", "--camera-position 0,-2,2", "--look-at 0,0,0.1"}) {
    const RunResult r =
        run("render " + path.string() + " -q -o " + (dir_ / "out/p.exr").string() + " " + option);
    EXPECT_EQ(r.status, 2) << option << ": " << r.output;
    const std::string name = std::string(option).substr(0, std::string(option).find(' '));
    EXPECT_EQ(r.output.rfind("meso: " + name + ": " + path.string() +
                                 " has a [path]: its keyframes place the camera",
                             0),
              0)
        << option << ": " << r.output;
  }
  EXPECT_TRUE(fs::is_empty(dir_ / "out"));
}

// Every option of `meso render --help` that takes a value shows its default (CLI11 writes it as
// "=VALUE" after the type); flags are off unless given, as the footer says.
TEST_F(RenderOptionsTest, HelpShowsEveryDefault) {
  const RunResult r = run("render --help");
  ASSERT_EQ(r.status, 0) << r.output;
  std::istringstream lines(r.output);
  std::string line;
  int withValue = 0;
  while (std::getline(lines, line)) {
    if (line.rfind("  -", 0) != 0) continue;
    std::istringstream words(line);
    std::string names, type;
    words >> names >> type;
    // A value's type name (CLI11's); a flag has its description there instead.
    bool typed = false;
    for (const char* t : {"TEXT", "INT", "UINT", "FLOAT"}) typed = typed || type.rfind(t, 0) == 0;
    if (!typed) continue;
    ++withValue;
    // The option's part of the line ends where two spaces start its description.
    const std::string option = line.substr(0, line.find("  ", 2));
    EXPECT_NE(option.find('='), std::string::npos) << "no default in: " << line;
  }
  EXPECT_GE(withValue, 20);
  EXPECT_NE(r.output.find("--spp INT:INT in [1 - 65536]=camera.spp"), std::string::npos);
  EXPECT_NE(r.output.find("Flags are off unless given"), std::string::npos);
}

}  // namespace
}  // namespace meso
