// The meso executable as a user meets it: exit status, messages and output files, for good and bad
// input. Each bad input must give status 2, a message naming FILE[:LINE:COL]: key, and no output.
#include "support/run_meso.h"
#include "support/temp_dir.h"

#include "meso/appearance/table_cache.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

using meso::testing::RunResult;
RunResult run(const std::string& args) { return meso::testing::runMeso(args); }

class CliTest : public meso::testing::TempDirTest {
 protected:
  void SetUp() override {
    meso::testing::TempDirTest::SetUp();
    std::filesystem::create_directories(dir_ / "out");
    write("quad.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
  }
  // A valid scene; `top` goes before every table, `camera` into [camera], `extra` at the end.
  std::string scene(const std::string& extra, const std::string& top = "",
                    const std::string& camera = "") {
    return top + "[camera]\nposition = [0, 0, 3]\n" +
           (camera.empty() ? "resolution = [32, 18]\nspp = 1\n" : camera) +
           "[[lights]]\ndirection = [0, 0, -1]\n[[objects]]\nmesh = \"quad.obj\"\nscheme = "
           "\"bilinear\"\n" +
           extra;
  }
  bool outputFolderEmpty() const { return fs::is_empty(dir_ / "out"); }
  RunResult render(const std::string& sceneText, const std::string& extraArgs = "") {
    write("scene.toml", sceneText);
    return run("render " + (dir_ / "scene.toml").string() + " -o " +
               (dir_ / "out/img.exr").string() + " -q " + extraArgs);
  }
};

// --version needs no subcommand: status 0 and the project's version (CMakeLists.txt).
TEST_F(CliTest, VersionPrintsTheProjectVersion) {
  const RunResult r = run("--version");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("meso " MESO_PROJECT_VERSION), std::string::npos) << r.output;
  EXPECT_EQ(run("").status, 2);  // still a subcommand without it
}

TEST_F(CliTest, ValidSceneWritesExrPngAndStats) {
  const RunResult r = render(scene(""), "--stats " + (dir_ / "out/stats.json").string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir_ / "out/img.exr"));
  EXPECT_TRUE(fs::exists(dir_ / "out/img.png"));
  std::ifstream in(dir_ / "out/stats.json");
  std::stringstream s;
  s << in.rdbuf();
  for (const char* key :
       {"\"seconds\"", "\"parse\"", "\"tessellate\"", "\"bvh\"", "\"render\"", "\"write\"",
        "\"total\"", "\"peak_rss_mib\"", "\"rays\"", "\"triangles\"", "\"settings\""})
    EXPECT_NE(s.str().find(key), std::string::npos) << key;
  EXPECT_NE(s.str().find("\"rays\": 576"), std::string::npos) << s.str();  // 32 x 18 x 1
}

// The displacement renderer from the command line: its stats keys, the micropolygon cap's
// warning, facet normals, and the transition overrides with their checks.
TEST_F(CliTest, DisplacementOptionsAndStats) {
  const std::string relief =
      "[[materials]]\nname = \"m\"\n  [[materials.relief]]\n  noise = { octaves = 2 }\n  amplitude "
      "= 0.01\n"
      "  scale = 4.0\n";
  const std::string sceneText = scene("material = \"m\"\n", "", "resolution = [64, 36]\nspp = 1\n");
  // The material table must come before [[objects]] uses it: put it first.
  write("scene.toml", relief + sceneText);
  const std::string base = "render " + (dir_ / "scene.toml").string() + " -o " +
                           (dir_ / "out/img.exr").string() + " -q ";
  RunResult r = run(base + "--algorithm displacement --dicing-rate 2 --stats " +
                    (dir_ / "out/stats.json").string());
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream in(dir_ / "out/stats.json");
  std::stringstream s;
  s << in.rdbuf();
  for (const char* key : {"\"micropolygons\"", "\"tessellate_seconds\"", "\"bvh_seconds\"",
                          "\"peak_mib_per_million_micropolygons\"", "\"dicing_rate\": 2.0",
                          "\"dicing_metric\": \"isotropic\"", "\"micropolygons_off_screen\""})
    EXPECT_NE(s.str().find(key), std::string::npos) << key << "\n" << s.str();
  EXPECT_EQ(s.str().find("\"micropolygons\": 0,"), std::string::npos) << s.str();
  // Geometry memory is Embree's peak plus what meso keeps of its meshes: the face and patch
  // coordinates of the few triangles outside Embree grids (none on this plane; the points go once
  // Embree has copied them, Displacement.ReleasingTheMeshPointsKeepsTheImage): less than the whole.
  const nlohmann::json stats = nlohmann::json::parse(s.str());
  const double mesh = stats.at("mesh_mib_per_million_micropolygons").get<double>();
  EXPECT_GE(mesh, 0.0);
  EXPECT_LT(mesh, stats.at("geometry_mib_per_million_micropolygons").get<double>());

  r = run(base + "--algorithm displacement --max-micropolygons 1000 --overwrite");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("would exceed the cap of 1000"), std::string::npos) << r.output;
  r = run(base + "--algorithm displacement --normals facet");
  EXPECT_EQ(r.status, 0) << r.output;
  r = run(base + "--algorithm displacement --dicing-metric projected --overwrite");
  EXPECT_EQ(r.status, 0) << r.output;
  r = run(base + "--D 0.5 --eps 0 --thresholds=-2,-1,1,2");
  EXPECT_EQ(r.status, 0) << r.output;
  fs::remove_all(dir_ / "out");
  fs::create_directories(dir_ / "out");
  r = run(base + "--thresholds=1,-1,0.3,2");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("thresholds must satisfy e1 < e2 < 0 < e3 < e4"), std::string::npos)
      << r.output;
  r = run(base + "--normals shiny");
  EXPECT_EQ(r.status, 2) << r.output;
  r = run(base + "--dicing-metric screen");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--dicing-metric"), std::string::npos) << r.output;
  EXPECT_TRUE(outputFolderEmpty());
}

struct BadInput {
  const char* name;
  std::string sceneExtra;   // appended to a valid scene
  std::string expected;     // substring of the message; {S} stands for the scene file's path
  std::string top = "";     // before every table of the scene
  std::string camera = "";  // replaces the keys of [camera]
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
      {"out of range", "[render]\nthreads = 5000\n",
       "{S}:11:11: render.threads: expected an integer in [0, 1024], got 5000"},
      {"bad enum", "[render]\nalgorithm = \"fast\"\n",
       "{S}:11:13: render.algorithm: expected one of auto"},
      {"malformed toml", "[render\n", "{S}:10:"},
      {"thresholds order", "[render]\nthresholds = [1, -0.3, 0.3, 1]\n",
       "{S}:11:14: render.thresholds:"},
      {"missing mesh", "[[objects]]\nmesh = \"absent.obj\"\n",
       "{S}:11:8: objects.mesh: file not found:"},
      {"mesh is a folder", "[[objects]]\nmesh = \"out\"\n",
       "{S}:11:8: objects.mesh: not a regular file"},
      {"empty mesh", "[[objects]]\nmesh = \"empty.obj\"\n", "empty.obj: empty mesh file"},
      {"mesh without faces", "[[objects]]\nmesh = \"nofaces.obj\"\n",
       "nofaces.obj: mesh has no faces"},
      {"garbage mesh", "[[objects]]\nmesh = \"garbage.obj\"\n",
       "garbage.obj:1:1: unexpected bytes \"??\" (not an OBJ statement"},
      {"unknown mesh format", "[[objects]]\nmesh = \"mesh.stl\"\n",
       "mesh.stl: unknown mesh format \".stl\""},
      {"absurd resolution", "", "camera.resolution: expected a number in [1, 16384]", "",
       "resolution = [100000, 10]\n"},
      {"absurd spp", "", "camera.spp: expected an integer in [1, 65536]", "", "spp = 10000000\n"},
      {"fractional resolution", "", "camera.resolution: expected two integers", "",
       "resolution = [32.5, 18]\n"},
      {"zero fov", "", "camera.fov: expected a number in (0, 180), got 0", "", "fov = 0\n"},
      {"negative intensity", "[[lights]]\nintensity = -1\n",
       "lights.intensity: expected a number in [0, 1e+12], got -1"},
      {"unknown light type", "[[lights]]\ntype = \"spot\"\n",
       "lights.type: expected one of directional | point"},
      {"zero light direction", "[[lights]]\ndirection = [0, 0, 0]\n",
       "lights.direction: expected a non-zero direction"},
      {"duplicate material", "[[materials]]\nname = \"a\"\n[[materials]]\nname = \"a\"\n",
       "materials.name: duplicate material name"},
      {"unknown material", "material = \"gold\"\n", "objects.material: no material named \"gold\""},
      {"missing height image",
       "[[materials]]\nname = \"m\"\n[[materials.relief]]\nheight = \"gone.png\"\n",
       "materials.relief.height: file not found"},
      {"relief with both sources",
       "[[materials]]\nname = \"m\"\n[[materials.relief]]\nheight = \"quad.obj\"\nnoise = {}\n",
       "materials.relief.height: expected exactly one of"},
      {"bad scale", "[[objects]]\nmesh = \"quad.obj\"\nscale = [1, 0, 1]\n",
       "objects.scale: expected non-zero scale factors"},
      {"bad dicing rate", "[render]\ndicing_rate = 0\n",
       "render.dicing_rate: expected a number in [0.01, 1000], got 0"},
      {"bad dicing metric", "[render]\ndicing_metric = \"screen\"\n",
       "render.dicing_metric: expected one of isotropic | projected"},
      {"path without keys", "[path]\nframes = 3\n", "path.keys: a [path] needs at least one"},
      {"path times out of order", "[path]\n[[path.keys]]\ntime = 1\n[[path.keys]]\ntime = 0\n",
       "path.keys.time: expected keyframe times to strictly increase"},
      {"string where table", "", "{S}:1:10: render: expected a table, got a string",
       "render = \"fast\"\n"},
  };
  const std::string scenePath = (dir_ / "scene.toml").string();
  for (const BadInput& c : cases) {
    std::string expected = c.expected;
    if (expected.rfind("{S}", 0) == 0) expected = scenePath + expected.substr(3);
    const RunResult r = render(scene(c.sceneExtra, c.top, c.camera));
    EXPECT_EQ(r.status, 2) << c.name << ": " << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos)
        << c.name << ": expected \"" << expected << "\" in\n"
        << r.output;
    EXPECT_TRUE(outputFolderEmpty()) << c.name;
  }
}

TEST_F(CliTest, MissingSceneFileAndBadOptions) {
  RunResult r =
      run("render " + (dir_ / "none.toml").string() + " -o " + (dir_ / "out/x.exr").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("none.toml: scene: file not found"), std::string::npos) << r.output;
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

// The extension is matched in any case; the PNG preview goes beside it.
TEST_F(CliTest, UpperCaseExrExtensionIsAccepted) {
  write("scene.toml", scene(""));
  const RunResult r =
      run("render " + (dir_ / "scene.toml").string() + " -q -o " + (dir_ / "out/X.EXR").string());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir_ / "out/X.EXR"));
  EXPECT_TRUE(fs::exists(dir_ / "out/X.png"));
}

// A cache folder of three tables, used 3, 2 and 1 hours ago by key.
class CliCacheTest : public CliTest {
 protected:
  void SetUp() override {
    CliTest::SetUp();
    cache_ = meso::TableCache(dir_ / "cache", uint64_t{1} << 40);
    const std::vector<float> table(1000, 0.5f);
    for (uint64_t key : {1, 2, 3}) {
      cache_.store(key, table, nullptr);
      fs::last_write_time(cache_.fileFor(key),
                          fs::file_time_type::clock::now() - std::chrono::hours(key));
    }
    fs::create_directories(cache_.folder() / "references");
    bytes_ = fs::file_size(cache_.fileFor(1));
  }
  RunResult runCache(const std::string& args) {
    return run("cache " + args + " --cache-dir " + cache_.folder().string());
  }
  meso::TableCache cache_{fs::path()};
  uint64_t bytes_ = 0;
};

TEST_F(CliCacheTest, ListShowsTablesLeastRecentlyUsedFirst) {
  const RunResult r = runCache("list");
  ASSERT_EQ(r.status, 0) << r.output;
  const size_t at3 = r.output.find("0000000000000003.tbl");
  const size_t at2 = r.output.find("0000000000000002.tbl");
  const size_t at1 = r.output.find("0000000000000001.tbl");
  ASSERT_NE(at1, std::string::npos) << r.output;
  EXPECT_TRUE(at3 < at2 && at2 < at1) << r.output;
  EXPECT_NE(r.output.find("total: 3 tables"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(std::to_string(3 * bytes_) + " bytes)"), std::string::npos) << r.output;
}

TEST_F(CliCacheTest, PruneThenClear) {
  RunResult r = runCache("prune --to " + std::to_string(2 * bytes_));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("removed 1 table "), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(cache_.fileFor(3)));  // the least recently used
  EXPECT_TRUE(fs::exists(cache_.fileFor(1)));
  r = runCache("clear");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("removed 2 tables"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(std::to_string(2 * bytes_) + " bytes"), std::string::npos) << r.output;
  EXPECT_TRUE(cache_.entries().empty());
  EXPECT_TRUE(fs::exists(cache_.folder() / "references"));
}

// A bad size, as an option or in MESO_CACHE_LIMIT: status 2 and a message naming where it came
// from.
TEST_F(CliTest, CacheBadSizesExitWithStatusTwo) {
  const std::string dirArg = " --cache-dir " + (dir_ / "cache").string();
  RunResult r = run("cache prune --to 12Q" + dirArg);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--to: expected a size in bytes"), std::string::npos) << r.output;
  setenv("MESO_CACHE_LIMIT", "plenty", 1);
  r = run("cache prune" + dirArg);
  unsetenv("MESO_CACHE_LIMIT");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("MESO_CACHE_LIMIT: expected a size in bytes"), std::string::npos)
      << r.output;
}

}  // namespace

namespace {

// `meso tables` on a scene whose algorithm reads no tables (bump) still builds and lists the
// tables of its relief levels (it used to crash with a segmentation fault there).
TEST_F(CliTest, TablesOfABumpSceneAreBuilt) {
  write("scene.toml",
        scene("material = \"m\"\n[[materials]]\nname = \"m\"\n[[materials.relief]]\nnoise = { "
              "octaves = 2 }\namplitude = 0.01\nscale = 2\n[render]\nalgorithm = \"bump\"\n"
              "cache_dir = \"cache\"\n"
              "[render.tables]\ntheta_v_bins = 4\ntheta_n_bins = 16\nphi_bins = 8\nphi_v_bins = "
              "2\nazimuths = 4\nrays_per_view = 64\nmesh_resolution = 16\nbrdf_theta_l = 4\n"
              "brdf_phi = 4\n"));
  const RunResult r = run("tables " + (dir_ / "scene.toml").string() + " --no-plots");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("\nm,1,"), std::string::npos) << r.output;
}

}  // namespace
