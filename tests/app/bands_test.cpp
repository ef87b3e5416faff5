// `meso bands`: the band images it writes sum back to the height map, low to high frequency.
#include "support/run_meso.h"
#include "support/temp_dir.h"

#include "meso/core/image_io.h"
#include "meso/core/math.h"
#include "meso/core/rng.h"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace meso {
namespace {

class BandsCommand : public testing::TempDirTest {
 protected:
  int run(const std::string& args, std::string* output = nullptr) {
    const testing::RunResult r = testing::runMeso("bands " + args);
    if (output) *output = r.output;
    return r.status;
  }
};

TEST_F(BandsCommand, BandsSumToTheMapAndRiseInFrequency) {
  Image map(64, 48, {"Y"});
  Rng rng(12);
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const float u = x / 64.0f, v = y / 48.0f;
      map.at(x, y, 0) = std::sin(2 * kPi * u) + 0.3f * std::cos(2 * kPi * (6 * u + 4 * v)) +
                        0.05f * rng.uniform();
    }
  writeExr(dir_ / "map.exr", map);
  std::string out;
  ASSERT_EQ(run((dir_ / "map.exr").string() + " -n 3 -o " + (dir_ / "bands").string(), &out), 0)
      << out;
  Image sum(64, 48, {"Y"});
  float previousFreq = -1.0f;
  for (int k = 1; k <= 3; ++k) {
    const Image band = readImage(dir_ / "bands" / ("map_band" + std::to_string(k) + ".exr"));
    ASSERT_EQ(band.width, 64);
    ASSERT_EQ(band.height, 48);
    for (size_t i = 0; i < sum.pixels.size(); ++i) sum.pixels[i] += band.pixels[i];
    // The CSV row of band k: "k,file,freq,..."; frequencies grow from band to band.
    std::string key =
        "\n";  // built step by step: GCC 12 warns falsely (-Wrestrict) on "\n" + string
    key += std::to_string(k);
    key += ',';
    const size_t row = out.find(key);
    ASSERT_NE(row, std::string::npos) << out;
    const size_t comma = out.find(',', out.find(',', row + 1) + 1);
    const float freq = std::stof(out.substr(comma + 1));
    EXPECT_GT(freq, previousFreq) << out;
    previousFreq = freq;
  }
  double worst = 0.0;
  for (size_t i = 0; i < sum.pixels.size(); ++i)
    worst = std::max(worst, double(std::abs(sum.pixels[i] - map.pixels[i])));
  EXPECT_LT(worst, 1e-5);
  EXPECT_NE(out.find("their sum reproduces it within"), std::string::npos);
}

TEST_F(BandsCommand, BadInputIsAClearError) {
  std::string out;
  EXPECT_EQ(run((dir_ / "absent.png").string(), &out), 2);
  EXPECT_NE(out.find("absent.png"), std::string::npos) << out;
  write("garbage.png", "not an image");
  EXPECT_EQ(run((dir_ / "garbage.png").string() + " -o " + (dir_ / "b").string(), &out), 2);
  EXPECT_NE(out.find("garbage.png"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "b" / "garbage_band1.exr"));
  Image map(8, 8, {"Y"});
  writeExr(dir_ / "m.exr", map);
  EXPECT_EQ(run((dir_ / "m.exr").string() + " -n 0", &out), 2);
  EXPECT_EQ(run((dir_ / "m.exr").string() + " -n 17", &out), 2);
}

// A map too small for the bands asked: refused before any output, naming the file and the most it
// splits into (a 1 x 1 map once wrote three "bands" with a crossover of 1 above one of 0.5); one
// band of a 1 x 1 map is the map itself.
TEST_F(BandsCommand, MapsTooSmallForTheBandsAreRefused) {
  Image one(1, 1, {"Y"});
  one.at(0, 0, 0) = 0.25f;
  writeExr(dir_ / "one.exr", one);
  std::string out;
  EXPECT_EQ(run((dir_ / "one.exr").string() + " -o " + (dir_ / "b").string(), &out), 2);
  EXPECT_NE(out.find("one.exr: --levels: band split: a 1 x 1 map splits into at most 1 band"),
            std::string::npos)
      << out;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "b")) << "nothing written";
  ASSERT_EQ(run((dir_ / "one.exr").string() + " -n 1 -o " + (dir_ / "b").string(), &out), 0) << out;
  EXPECT_EQ(readImage(dir_ / "b" / "one_band1.exr").at(0, 0, 0), 0.25f);
  Image small(16, 16, {"Y"});
  writeExr(dir_ / "s.exr", small);
  EXPECT_EQ(run((dir_ / "s.exr").string() + " -n 4 -o " + (dir_ / "c").string(), &out), 2);
  EXPECT_NE(out.find("at most 3 bands"), std::string::npos) << out;
  EXPECT_EQ(run((dir_ / "s.exr").string() + " -n 3 -o " + (dir_ / "c").string(), &out), 0) << out;
}

}  // namespace
}  // namespace meso
