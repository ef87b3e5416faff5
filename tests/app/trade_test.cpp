// `meso trade` from the command line on a tiny default scene: the CSV's exact header, one row per
// configuration, finite non-negative errors, zero error for a configuration identical to the
// reference, the plot, the summary, --temporal, and status 2 naming the option for bad values.
#include "support/run_meso.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

using meso::testing::RunResult;
RunResult run(const std::string& args) { return meso::testing::runMeso(args); }

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> fields;
  std::stringstream s(line);
  std::string f;
  while (std::getline(s, f, sep)) fields.push_back(f);
  if (!line.empty() && line.back() == sep) fields.emplace_back();
  return fields;
}

std::vector<std::string> lines(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> result;
  for (std::string l; std::getline(in, l);) result.push_back(l);
  return result;
}

class TradeTest : public meso::testing::TempDirTest {
 protected:
  std::string scene(const char* name) const { return std::string(MESO_SOURCE_DIR) + "/scenes/" + name; }
  std::string out() const { return (dir_ / "trade").string(); }
  // Small sweeps: 1 reference + 2 x 2 hybrid (D 2, 4 spp is the scene's own) + 2 x 2 displacement.
  std::string tiny() const {
    return "--width 48 --height 27 --reference-spp 4 --reference-dicing-rate 2 --d-values 1,2 --spp-values 1,4 "
           "--dicing-rates 4,2 -o " + out();
  }
};

TEST_F(TradeTest, CsvRowsErrorsPlotAndSummary) {
  const RunResult r = run("trade " + scene("default.toml") + " " + tiny());
  ASSERT_EQ(r.status, 0) << r.output;
  const std::vector<std::string> rows = lines(dir_ / "trade/trade.csv");
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows[0],
            "name,algorithm,D,spp,dicing_rate,seconds,peak_rss_mib,micropolygons,mean_abs_error,rmse,"
            "mean_intensity_error_pct");
  ASSERT_EQ(rows.size(), 1u + 1u + 4u + 4u) << r.output;
  std::map<std::string, std::vector<std::string>> byName;
  for (size_t i = 1; i < rows.size(); ++i) {
    const std::vector<std::string> f = split(rows[i], ',');
    ASSERT_EQ(f.size(), 11u) << rows[i];
    for (int c : {5, 6, 8, 9, 10}) {
      const double v = std::stod(f[c]);
      EXPECT_TRUE(std::isfinite(v) && v >= 0.0) << rows[i];
    }
    EXPECT_GT(std::stod(f[5]), 0.0) << rows[i];  // seconds
    byName[f[0]] = f;
  }
  ASSERT_TRUE(byName.count("reference"));
  EXPECT_EQ(byName["reference"][1], "displacement");
  EXPECT_EQ(std::stod(byName["reference"][8]), 0.0);
  // Same algorithm, dicing rate, spp and seed as the reference: the renderer is deterministic.
  ASSERT_TRUE(byName.count("displacement_r2_spp4"));
  EXPECT_EQ(std::stod(byName["displacement_r2_spp4"][8]), 0.0);
  EXPECT_EQ(std::stod(byName["displacement_r2_spp4"][9]), 0.0);
  ASSERT_TRUE(byName.count("hybrid_D2_spp4"));
  EXPECT_EQ(byName["hybrid_D2_spp4"][1], "auto");
  EXPECT_GT(std::stod(byName["hybrid_D1_spp1"][8]), 0.0);  // one sample per pixel is not converged
  EXPECT_TRUE(fs::exists(dir_ / "trade/trade.png"));
  EXPECT_GT(fs::file_size(dir_ / "trade/trade.png"), 1000u);
  EXPECT_NE(r.output.find("trade: default hybrid (D 2, 4 spp)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("speedup"), std::string::npos) << r.output;  // displacement_r2_spp4 is as accurate
}

TEST_F(TradeTest, TemporalBandsOnAPath) {
  const RunResult r = run("trade " + scene("flythrough.toml") +
                          " --width 64 --height 36 --frames 0:2 --temporal-only --reference-spp 4 -o " + out());
  ASSERT_EQ(r.status, 0) << r.output;
  const std::vector<std::string> rows = lines(dir_ / "trade/temporal.csv");
  ASSERT_EQ(rows.size(), 7u) << r.output;
  EXPECT_EQ(rows[0], "band,threshold,half_width,pixels,hybrid_mean_abs_change,reference_mean_abs_change,ratio");
  const std::vector<std::string> all = split(rows[6], ',');
  ASSERT_EQ(all[0], "all");
  EXPECT_GT(std::stod(all[3]), 0.0);  // pixels that hit a surface, over two frame pairs
  EXPECT_EQ(lines(dir_ / "trade/trade.csv").size(), 3u);  // header, reference, default hybrid
}

TEST_F(TradeTest, BadValuesExitTwoNamingTheOption) {
  const std::string base = "trade " + scene("default.toml") + " --width 48 --height 27 -o " + out() + " ";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--d-values -1", "--d-values"},
      {"--spp-values 4,0", "--spp-values"},
      {"--dicing-rates abc", "--dicing-rates"},
      {"--dicing-rates 0", "--dicing-rates"},
      {"--reference-spp 0", "--reference-spp"},
      {"--reference-dicing-rate -2", "--reference-dicing-rate"},
      {"--frames 0:3", "--frames"},
      {"--temporal", "--temporal"},
  };
  for (const auto& [args, option] : cases) {
    const RunResult r = run(base + args);
    EXPECT_EQ(r.status, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(option), std::string::npos) << args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "trade/trade.csv")) << args;
  }
  const RunResult missing = run("trade " + (dir_ / "nope.toml").string() + " -o " + out());
  EXPECT_EQ(missing.status, 2) << missing.output;
}

}  // namespace
