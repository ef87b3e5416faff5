// Scene keys set from the command line (SceneOverride): applied before the reader runs, so they
// are checked exactly as the file's keys, and every error names the option and the key.
#include "meso/core/error.h"
#include "meso/scene/scene_parser.h"

#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace meso {
namespace {

class SceneOverridesTest : public testing::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    write("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  }
  Scene parse(const std::vector<SceneOverride>& overrides, const std::string& extra = "") {
    return parseScene(std::string(kScene) + extra, dir_ / "scene.toml", overrides);
  }
  std::string errorOf(const std::vector<SceneOverride>& overrides, const std::string& extra = "") {
    try {
      parse(overrides, extra);
    } catch (const Error& e) {
      return e.what();
    }
    ADD_FAILURE() << "no error for " << overrides.front().key << "=" << overrides.front().value;
    return "";
  }
  static SceneOverride set(const std::string& key, const std::string& value) {
    return {.origin = "--set", .key = key, .value = value};
  }
  static constexpr const char* kScene =
      "[camera]\nfov = 40\nresolution = [64, 48]\n"
      "[[materials]]\nname = \"a\"\nkd = 0.2\n[[materials]]\nname = \"b\"\nkd = 0.3\n"
      "[[objects]]\nmesh = \"quad.obj\"\nmaterial = \"b\"\n";
};

TEST_F(SceneOverridesTest, ValuesReplaceTheFilesAndFillTablesItLacks) {
  const Scene s = parse({set("camera.fov", "30"), set("camera.resolution", "[320, 180]"),
                         set("render.D", "3.5"), set("render.algorithm", "bump"),
                         set("render.shadows", "false"), set("materials[1].kd", "[0.5,0.25,1]"),
                         set("camera.fov", "25")});
  EXPECT_FLOAT_EQ(s.camera.fovY, 25.0f) << "the last of two overrides of one key wins";
  EXPECT_EQ(s.camera.width, 320);
  EXPECT_EQ(s.camera.height, 180);
  EXPECT_FLOAT_EQ(s.render.transition.D, 3.5f) << "[render] created";
  EXPECT_EQ(s.render.algorithm, Algorithm::Bump) << "a bare word is a string";
  EXPECT_FALSE(s.render.shadows);
  EXPECT_FLOAT_EQ(s.materials[0].kd.x, 0.2f) << "materials[0] untouched";
  EXPECT_FLOAT_EQ(s.materials[1].kd.x, 0.5f);
  EXPECT_FLOAT_EQ(s.materials[1].kd.y, 0.25f);
  EXPECT_FLOAT_EQ(s.materials[1].kd.z, 1.0f);
  // No overrides: the file's values.
  const Scene plain = parse({});
  EXPECT_FLOAT_EQ(plain.camera.fovY, 40.0f);
  EXPECT_EQ(plain.camera.width, 64);
}

// The reader's own checks, with the option in place of FILE:LINE:COL.
TEST_F(SceneOverridesTest, ValuesAreCheckedLikeTheFile) {
  EXPECT_EQ(errorOf({set("camera.fov", "200")}),
            "--set: camera.fov: expected a number in (0, 180), got 200");
  EXPECT_EQ(errorOf({set("camera.resolution", "[320]")}),
            "--set: camera.resolution: expected an array of 2 numbers, got an array of 1");
  EXPECT_EQ(errorOf({set("render.shadows", "1")}),
            "--set: render.shadows: expected true or false, got 1");
  EXPECT_EQ(errorOf({set("materials[0].kd", "[0.5, -1, 0.5]")}),
            "--set: materials.kd: expected a number in [0, 1e+06], got -1");
  const std::string unknown = errorOf({set("render.dee", "3")});
  EXPECT_EQ(unknown.rfind("--set: render.dee: unknown key (allowed here: ", 0), 0) << unknown;
  const std::string table = errorOf({set("colour.x", "3")});
  EXPECT_EQ(table.rfind("--set: colour: unknown key", 0), 0) << table;
  EXPECT_EQ(errorOf({{.origin = "--fov", .key = "camera.fov", .value = "0"}}),
            "--fov: camera.fov: expected a number in (0, 180), got 0");
  // A bad value in the file is still reported at its line.
  const std::string file = errorOf({set("camera.fov", "30")}, "[render]\nD = -1\n");
  EXPECT_NE(file.find("scene.toml:14:5: render.D: "), std::string::npos) << file;
}

TEST_F(SceneOverridesTest, MalformedKeysAndValuesNameTheOption) {
  const std::string key = "expected a dotted scene key such as camera.fov, render.D or ";
  for (const char* bad : {"", "camera.", ".fov", "camera..fov", "camera fov", "materials[x].kd",
                          "materials[1.kd", "materials[].kd", "materials[1]kd"}) {
    const std::string e = errorOf({set(bad, "1")});
    EXPECT_EQ(e.rfind("--set: " + key, 0), 0) << bad << ": " << e;
  }
  EXPECT_EQ(errorOf({set("materials[2].kd", "1")}),
            "--set: materials: expected an index below 2 (the scene has 2 [[materials]] "
            "entries), got 2");
  EXPECT_EQ(errorOf({set("lights[0].direction", "[0, 0, -1]")}),
            "--set: lights: expected an index below 0 (the scene has 0 [[lights]] entries), got 0");
  EXPECT_EQ(errorOf({set("camera.fov.x", "1")}),
            "--set: camera.fov: expected a table to set camera.fov.x in, got 40");
  for (const char* bad : {"[1, 2", "3x", "-x", "\"open", "1 2", "", "a\001b", "a\377b"}) {
    const std::string e = errorOf({set("camera.fov", bad)});
    EXPECT_EQ(e.rfind("--set: camera.fov: expected a TOML value", 0), 0) << bad << ": " << e;
  }
}

}  // namespace
}  // namespace meso
