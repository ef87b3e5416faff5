// `meso trade` from the command line on a tiny default scene: the CSV's exact header, one row per
// configuration, finite non-negative errors, zero error for a configuration identical to the
// reference, the plot, the summary, --temporal, the reference's convergence (converged, or a
// warning with the last change when the budget is too small), the reference cache (hit on a
// second run, a corrupt file re-rendered), and status 2 naming the option for bad values.
#include "support/run_meso.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
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

// The CSV without its comment lines (the reference's convergence), and those lines alone.
std::vector<std::string> dataLines(const fs::path& file) {
  std::vector<std::string> result;
  for (const std::string& l : lines(file))
    if (l.empty() || l[0] != '#') result.push_back(l);
  return result;
}
// The reference's comment lines: the plot's ("# pareto_front:", "# default_hybrid:") left out.
bool plotComment(const std::string& l) {
  return l.rfind("# pareto_front:", 0) == 0 || l.rfind("# default_hybrid:", 0) == 0;
}
std::vector<std::string> commentLines(const fs::path& file) {
  std::vector<std::string> result;
  for (const std::string& l : lines(file))
    if (!l.empty() && l[0] == '#' && !plotComment(l)) result.push_back(l);
  return result;
}
// The value of the plot comment "# KEY: VALUE", or "" (and a failure) if there is none.
std::string plotLine(const fs::path& file, const std::string& key) {
  for (const std::string& l : lines(file))
    if (l.rfind("# " + key + ": ", 0) == 0) return l.substr(key.size() + 4);
  ADD_FAILURE() << "no # " << key << " line in " << file;
  return "";
}

// The number after "key " in text, up to the next ',' or ' '.
double numberAfter(const std::string& text, const std::string& key) {
  const size_t at = text.find(key + " ");
  if (at == std::string::npos) return std::nan("");
  return std::stod(text.substr(at + key.size() + 1));
}

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

class TradeTest : public meso::testing::TempDirTest {
 protected:
  std::string scene(const char* name) const {
    return std::string(MESO_SOURCE_DIR) + "/scenes/" + name;
  }
  std::string out() const { return (dir_ / "trade").string(); }
  std::string cache() const { return (dir_ / "references").string(); }
  // Small sweeps: a one-level reference + 2 x 2 hybrid over D (D 2, 1 px, 4 spp is the scene's own)
  // + 1 x 2 more hybrid over dicing (2 px) + 2 x 2 x 2 displacement (relief samples 0 and 4).
  std::string tiny() const {
    return "--width 48 --height 27 --reference-spp 4 --reference-dicing-rate 2 "
           "--reference-max-refinements 0 "
           "--d-values 1,2 --spp-values 1,4 --dicing-rates 4,2 --hybrid-dicing-rates 2,1 "
           "--reference-cache " +
           cache() + " -o " + out();
  }
  // The reference alone is what these tests look at: one cheap hybrid and displacement
  // configuration.
  std::string referenceOnly() const {
    return "--width 48 --height 27 --reference-spp 4 --reference-dicing-rate 2 --d-values 2 "
           "--spp-values 4 "
           "--dicing-rates 4 --hybrid-dicing-rates 1 --reference-cache " +
           cache() + " -o " + out() + " ";
  }
};

TEST_F(TradeTest, CsvRowsErrorsPlotAndSummary) {
  const RunResult r = run("trade " + scene("torus_floor.toml") + " " + tiny());
  ASSERT_EQ(r.status, 0) << r.output;
  const std::vector<std::string> rows = dataLines(dir_ / "trade/trade.csv");
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows[0],
            "name,algorithm,D,spp,dicing_rate,relief_samples,seconds,peak_rss_mib,micropolygons,"
            "mean_abs_error,rmse,"
            "mean_intensity_error_pct,geometry_mib,peak_added_mib,worst_band_error_pct,"
            "worst_contrast_ratio");
  ASSERT_EQ(rows.size(), 1u + 1u + 4u + 2u + 8u) << r.output;
  std::map<std::string, std::vector<std::string>> byName;
  for (size_t i = 1; i < rows.size(); ++i) {
    const std::vector<std::string> f = split(rows[i], ',');
    ASSERT_EQ(f.size(), 16u) << rows[i];
    EXPECT_TRUE(std::isfinite(std::stod(f[14]))) << rows[i];
    // The local contrast ratio, empty where no depth band of the reference shows relief.
    if (!f[15].empty()) {
      EXPECT_TRUE(std::isfinite(std::stod(f[15])) && std::stod(f[15]) >= 0.0) << rows[i];
    }
    for (int c : {6, 7, 9, 10, 11, 12, 13}) {
      const double v = std::stod(f[c]);
      EXPECT_TRUE(std::isfinite(v) && v >= 0.0) << rows[i];
    }
    EXPECT_GT(std::stod(f[6]), 0.0) << rows[i];  // seconds
    // What the configuration added above the process's resident memory is its peak without the
    // process's baseline (its libraries alone are tens of MiB), so clearly less than the peak.
    EXPECT_GE(std::stod(f[13]), 0.0) << rows[i];
    EXPECT_LT(std::stod(f[13]), std::stod(f[7]) - 20.0) << rows[i];
    byName[f[0]] = f;
  }
  ASSERT_TRUE(byName.count("reference"));
  EXPECT_EQ(byName["reference"][1], "displacement");
  EXPECT_EQ(std::stod(byName["reference"][9]), 0.0);
  EXPECT_EQ(std::stod(byName["reference"][14]), 0.0);
  if (!byName["reference"][15].empty()) {
    EXPECT_EQ(std::stod(byName["reference"][15]), 1.0);
  }
  // One sample per pixel of the hybrid differs from the reference in some depth band's mean.
  EXPECT_NE(std::stod(byName["hybrid_D1_r1_spp1"][14]), 0.0);
  // Same algorithm, dicing rate, spp and seed as the reference: the renderer is deterministic.
  ASSERT_TRUE(byName.count("displacement_r2_rs4_spp4"));
  EXPECT_EQ(std::stod(byName["displacement_r2_rs4_spp4"][9]), 0.0);
  EXPECT_EQ(std::stod(byName["displacement_r2_rs4_spp4"][10]), 0.0);
  if (!byName["displacement_r2_rs4_spp4"][15].empty()) {
    EXPECT_EQ(std::stod(byName["displacement_r2_rs4_spp4"][15]), 1.0);
  }
  EXPECT_GT(std::stod(byName["reference"][12]), 0.0);  // geometry memory of displaced micropolygons
  // Rendering the reference needs memory of its own (its micropolygons, its film), above the
  // process's baseline.
  EXPECT_GT(std::stod(byName["reference"][13]), 0.0) << rows[1];
  ASSERT_TRUE(byName.count("hybrid_D2_r1_spp4"));
  EXPECT_EQ(byName["hybrid_D2_r1_spp4"][1], "auto");
  ASSERT_TRUE(byName.count("hybrid_D2_r2_spp1"));  // the hybrid's dicing rate is swept too
  EXPECT_EQ(byName["hybrid_D2_r2_spp1"][4], "2");
  EXPECT_GT(std::stod(byName["hybrid_D1_r1_spp1"][9]),
            0.0);  // one sample per pixel is not converged
  // The plot's inputs are in the CSV: the Pareto front (names by time, none dominated) and the
  // scene's own hybrid; tools/plot_trade.py draws trade.png from them.
  EXPECT_EQ(plotLine(dir_ / "trade/trade.csv", "default_hybrid"), "hybrid_D2_r1_spp4");
  const std::vector<std::string> front =
      split(plotLine(dir_ / "trade/trade.csv", "pareto_front"), ';');
  ASSERT_FALSE(front.empty());
  double lastSeconds = 0.0, lastRmse = 1e30;
  for (const std::string& name : front) {
    ASSERT_TRUE(byName.count(name)) << name;
    EXPECT_NE(name.rfind("reference", 0), 0u) << name;
    EXPECT_GE(std::stod(byName[name][6]), lastSeconds) << name;
    EXPECT_LT(std::stod(byName[name][10]), lastRmse) << name;
    lastSeconds = std::stod(byName[name][6]), lastRmse = std::stod(byName[name][10]);
  }
  EXPECT_TRUE(fs::exists(dir_ / "trade/trade.png")) << r.output;
  EXPECT_GT(fs::file_size(dir_ / "trade/trade.png"), 1000u);
  EXPECT_NE(r.output.find("trade: default hybrid (D 2, 1 px, 4 spp)"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("trade: as consistent and as detailed too (every depth band's mean "
                          "within "),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("\ntrade: cheapest hybrid swept within 0.5% of the reference in every "
                          "depth band and 10% in local contrast: "),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("speedup"), std::string::npos)
      << r.output;  // displacement_r2_rs4_spp4 is as accurate
  const std::string x = "[0-9.e+-]+x";
  // What each added above the baseline: "n/a" when displacement's peak did not rise above it (as
  // can happen under ASan), never "infx".
  EXPECT_EQ(r.output.find("infx"), std::string::npos) << r.output;
  EXPECT_TRUE(std::regex_search(
      r.output,
      std::regex("hybrid / displacement at equal rmse: time " + x + ", peak memory " + x + " \\((" +
                 x + "|n/a) of what each added above the process's baseline\\), " +
                 "geometry memory " + x + ", micropolygons " + x + ", spp " + x)))
      << r.output;
  // One reference level cannot say how converged it is: the warning says so.
  EXPECT_NE(r.output.find("reference NOT converged: only one level"), std::string::npos)
      << r.output;
}

// Tolerances the tiny default scene meets after one refinement (2 px 4 spp -> 1 px 8 spp).
TEST_F(TradeTest, ReferenceThatConvergesIsReportedConverged) {
  const RunResult r = run("trade " + scene("torus_floor.toml") + " " + referenceOnly() +
                          "--reference-tolerance 1 --reference-rmse-tolerance 10");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.find("WARNING"), std::string::npos) << r.output;
  EXPECT_NE(
      r.output.find(
          "trade: reference converged (the mean of every depth band changed by less than 1%, the "
          "rmse is below 10% of the mean): 2 px 4/wavelength 4 spp -> 1 px 8/wavelength 8 spp "
          "(worst "
          "band "),
      std::string::npos)
      << r.output;
  const std::vector<std::string> comments = commentLines(dir_ / "trade/trade.csv");
  ASSERT_EQ(comments.size(), 3u) << r.output;  // verdict, level 0, level 1
  EXPECT_NE(comments[0].find("# reference converged"), std::string::npos) << comments[0];
  const double meanChange = numberAfter(comments[2], "mean_change_pct");
  const double rmseChange = numberAfter(comments[2], "rmse_change_pct");
  EXPECT_LT(std::abs(meanChange), 1.0);
  EXPECT_LT(rmseChange, 10.0);
  EXPECT_GT(rmseChange, 0.0);  // 4 and 8 spp differ
  // Five depth bands, near to far; the reported change is the largest in magnitude.
  const size_t at = comments[2].find("band_change_pct ");
  ASSERT_NE(at, std::string::npos) << comments[2];
  const std::vector<std::string> bands = split(comments[2].substr(at + 16), ';');
  ASSERT_EQ(bands.size(), 5u) << comments[2];
  double worst = 0.0;
  for (const std::string& b : bands)
    if (std::abs(std::stod(b)) > std::abs(worst)) worst = std::stod(b);
  EXPECT_NEAR(worst, meanChange, 1e-4 + 1e-4 * std::abs(meanChange));
  EXPECT_GT(std::abs(worst), 0.0);
  std::map<std::string, std::vector<std::string>> byName;
  for (const std::string& row : dataLines(dir_ / "trade/trade.csv"))
    byName[split(row, ',')[0]] = split(row, ',');
  ASSERT_TRUE(byName.count("reference_l0") && byName.count("reference"));
  EXPECT_EQ(byName["reference"][3], "8");
  EXPECT_EQ(byName["reference"][4], "1");
  // Each refinement also doubles the micropolygons per relief wavelength (render.relief_samples).
  EXPECT_EQ(byName["reference_l0"][5], "4");
  EXPECT_EQ(byName["reference"][5], "8");
  EXPECT_GT(std::stod(byName["reference_l0"][10]), 0.0);  // measured against the finer level
}

// A budget of one refinement and a tolerance no render meets: a loud warning with the last change,
// exit status 0, the sweep still written. A micropolygon budget below the next level stops earlier.
TEST_F(TradeTest, ReferenceOverItsBudgetWarnsWithTheLastChange) {
  RunResult r = run("trade " + scene("torus_floor.toml") + " " + referenceOnly() +
                    "--reference-max-refinements 1 --reference-tolerance 0.0001 "
                    "--reference-rmse-tolerance 0.0001");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("meso: WARNING: reference NOT converged"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--reference-max-refinements 1 reached"), std::string::npos) << r.output;
  const std::string phrase = "the last refinement still changed the mean of a depth band by ";
  const size_t at = r.output.find(phrase);
  ASSERT_NE(at, std::string::npos) << r.output;
  const double reported = std::stod(r.output.substr(at + phrase.size()));
  const std::vector<std::string> comments = commentLines(dir_ / "trade/trade.csv");
  ASSERT_EQ(comments.size(), 3u);
  EXPECT_NE(comments[0].find("# reference NOT converged"), std::string::npos) << comments[0];
  EXPECT_NEAR(reported, numberAfter(comments[2], "mean_change_pct"), 0.006);
  EXPECT_GT(std::abs(numberAfter(comments[2], "mean_change_pct")) +
                numberAfter(comments[2], "rmse_change_pct"),
            0.0001);
  EXPECT_EQ(dataLines(dir_ / "trade/trade.csv").size(),
            1u + 2u + 1u + 2u);  // header, levels, hybrid, displacement (relief samples 0, 4)

  // Level 0 has 4204 micropolygons here; the next would need about 4x.
  r = run("trade " + scene("torus_floor.toml") + " " + referenceOnly() +
          "--reference-max-micropolygons 10000");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("over --reference-max-micropolygons 10000"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("WARNING: reference NOT converged: only one level"), std::string::npos)
      << r.output;
}

// The second run takes every reference level from the cache and gets the same CSV rows for them; a
// corrupt cache file is reported, re-rendered and replaced.
TEST_F(TradeTest, ReferenceLevelsComeFromTheCacheOnASecondRun) {
  const std::string args = "trade " + scene("torus_floor.toml") + " " + referenceOnly() +
                           "--reference-max-refinements 2";
  const RunResult first = run(args);
  ASSERT_EQ(first.status, 0) << first.output;
  EXPECT_EQ(count(first.output, "from cache"), 0u) << first.output;
  const std::vector<std::string> before = dataLines(dir_ / "trade/trade.csv");
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(cache())) files.push_back(e.path());
  // Two files per level: its render and the same render with the second seed (sampling noise).
  ASSERT_EQ(files.size(), 6u);

  const RunResult second = run(args);
  ASSERT_EQ(second.status, 0) << second.output;
  EXPECT_EQ(count(second.output, "from cache"), 3u) << second.output;
  const std::vector<std::string> after = dataLines(dir_ / "trade/trade.csv");
  ASSERT_GE(after.size(), 4u);
  for (size_t i = 1; i <= 3; ++i) EXPECT_EQ(after[i], before[i]);  // the levels, seconds included

  // Truncate one file: its level is re-rendered (with a message), and the next run trusts the new
  // files.
  fs::resize_file(files[0], fs::file_size(files[0]) / 2);
  const RunResult third = run(args);
  ASSERT_EQ(third.status, 0) << third.output;
  EXPECT_NE(third.output.find("re-rendering the reference"), std::string::npos) << third.output;
  EXPECT_EQ(count(third.output, "from cache"), 2u) << third.output;
  const RunResult fourth = run(args);
  EXPECT_EQ(count(fourth.output, "from cache"), 3u) << fourth.output;
  // A different setting that shapes the image is another key.
  const RunResult other = run(args + " --width 40");
  EXPECT_EQ(count(other.output, "from cache"), 0u) << other.output;
}

TEST_F(TradeTest, TemporalBandsOnAPath) {
  const RunResult r = run("trade " + scene("flythrough.toml") +
                          " --width 64 --height 36 --frames 0:2 --temporal-only --reference-spp 4 "
                          "--reference-max-refinements 1 --reference-cache " +
                          cache() + " -o " + out());
  ASSERT_EQ(r.status, 0) << r.output;
  const std::vector<std::string> rows = lines(dir_ / "trade/temporal.csv");
  ASSERT_EQ(rows.size(), 7u) << r.output;
  EXPECT_EQ(
      rows[0],
      "band,threshold,half_width,pixels,hybrid_mean_abs_change,reference_mean_abs_change,ratio");
  const std::vector<std::string> all = split(rows[6], ',');
  ASSERT_EQ(all[0], "all");
  EXPECT_GT(std::stod(all[3]), 0.0);  // pixels that hit a surface, over two frame pairs
  EXPECT_EQ(dataLines(dir_ / "trade/trade.csv").size(),
            4u);  // header, 2 reference levels, default hybrid
}

TEST_F(TradeTest, BadValuesExitTwoNamingTheOption) {
  const std::string base =
      "trade " + scene("torus_floor.toml") + " --width 48 --height 27 -o " + out() + " ";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--d-values -1", "--d-values"},
      {"--spp-values 4,0", "--spp-values"},
      {"--dicing-rates abc", "--dicing-rates"},
      {"--dicing-rates 0", "--dicing-rates"},
      {"--reference-spp 0", "--reference-spp"},
      {"--reference-dicing-rate -2", "--reference-dicing-rate"},
      {"--reference-tolerance 0", "--reference-tolerance"},
      {"--reference-max-refinements 13", "--reference-max-refinements"},
      {"--hybrid-dicing-rates 0", "--hybrid-dicing-rates"},
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
