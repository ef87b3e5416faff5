// `meso tables` plots (src/app/tables_command.cpp, tools/plot_tables.py): each level's histogram
// and BRDF table as CSV and as a matplotlib PNG beside it; without matplotlib a warning says how to
// plot the CSVs, which are kept, and no PNG is left behind.
#include "support/run_meso.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace meso {
namespace {

namespace fs = std::filesystem;

using testing::RunResult;

// Whether the python3 meso runs (Debian's first) imports matplotlib.
bool hasMatplotlib() {
  const char* py = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  return std::system((std::string(py) + " -c 'import matplotlib' >/dev/null 2>&1").c_str()) == 0;
}

bool hasPython() {
  return fs::exists("/usr/bin/python3") || std::system("command -v python3 >/dev/null 2>&1") == 0;
}

bool isPng(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  char magic[8] = {};
  in.read(magic, sizeof magic);
  return in && std::string(magic, 8) == "\x89PNG\r\n\x1a\n";
}

class TablesPlotsTest : public testing::TempDirTest {
 protected:
  void SetUp() override {
    testing::TempDirTest::SetUp();
    write("quad.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
    write("scene.toml",
          "[camera]\nposition = [0, 0, 3]\nresolution = [32, 18]\nspp = 1\n[[lights]]\n"
          "direction = [0, 0, -1]\n[[objects]]\nmesh = \"quad.obj\"\nscheme = \"bilinear\"\n"
          "material = \"m\"\n[[materials]]\nname = \"m\"\n[[materials.relief]]\nnoise = { "
          "octaves = 2 }\namplitude = 0.01\nscale = 2\n[render]\ncache_dir = \"cache\"\n"
          "[render.tables]\ntheta_v_bins = 4\ntheta_n_bins = 16\nphi_bins = 8\nphi_v_bins = 2\n"
          "azimuths = 4\nrays_per_view = 64\nmesh_resolution = 16\nbrdf_theta_l = 4\n"
          "brdf_phi = 4\n");
  }
  RunResult tables() {
    return testing::runMeso("tables " + (dir_ / "scene.toml").string() + " -o " +
                            (dir_ / "plots").string());
  }
};

TEST_F(TablesPlotsTest, EachTableIsPlottedFromItsCsv) {
  if (!hasMatplotlib())
    GTEST_SKIP() << "python3 has no matplotlib (apt-get install python3-matplotlib)";
  const RunResult r = tables();
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.find("not plotted"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("meso: plots in"), std::string::npos) << r.output;
  for (const char* kind : {"histogram", "brdf"}) {
    const fs::path stem = dir_ / "plots" / (std::string("m_level1_") + kind);
    EXPECT_GT(fs::file_size(stem.string() + ".csv"), 100u) << kind;
    EXPECT_TRUE(isPng(stem.string() + ".png")) << kind;
    // An axes, labels and colour bar figure, not a few-pixel heat map.
    EXPECT_GT(fs::file_size(stem.string() + ".png"), 20000u) << kind;
  }
}

// A python3 whose matplotlib fails to import (a module of that name first on PYTHONPATH) stands in
// for one without matplotlib.
TEST_F(TablesPlotsTest, WithoutMatplotlibTheCsvsStayAndAWarningSaysHowToPlotThem) {
  if (!hasPython()) GTEST_SKIP() << "no python3";
  fs::create_directories(dir_ / "fake/matplotlib");
  fs::create_directories(dir_ / "plots");
  write("fake/matplotlib/__init__.py", "raise ImportError('no matplotlib here')\n");
  write("plots/m_level1_brdf.png", "a plot of an earlier run");
  setenv("PYTHONPATH", (dir_ / "fake").c_str(), 1);
  const RunResult r = tables();
  unsetenv("PYTHONPATH");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("meso: warning: tables not plotted (needs python3 with matplotlib"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("plot_tables.py"), std::string::npos) << r.output;
  for (const char* kind : {"histogram", "brdf"}) {
    const fs::path stem = dir_ / "plots" / (std::string("m_level1_") + kind);
    EXPECT_TRUE(fs::exists(stem.string() + ".csv")) << kind;
    EXPECT_FALSE(fs::exists(stem.string() + ".png")) << kind;
  }
}

}  // namespace
}  // namespace meso
