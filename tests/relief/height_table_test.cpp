// Height tables from images: conventions, luminance, frequency, and bad files as clear errors.
#include "meso/relief/height_table.h"
#include "meso/core/error.h"
#include "meso/core/image_io.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

namespace meso {
namespace {

namespace fs = std::filesystem;
using HeightTableFiles = testing::TempDirTest;

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

#define EXPECT_HAS(text, part) EXPECT_NE(std::string(text).find(part), std::string::npos) << (text)

TEST(HeightTable, TexelCentresRowsAndLuminance) {
  Image img(3, 2, {"R", "G", "B", "A"});
  img.at(1, 0, 0) = 1.0f;  // top row, middle: R only
  img.at(2, 1, 1) = 1.0f;  // bottom row, right: G only
  const HeightTable t(img, "rgba.png");
  // Image row 0 is the top: table row 1 (v grows upwards).
  EXPECT_NEAR(t.texel(1, 1), 0.2126f, 1e-6f);
  EXPECT_NEAR(t.texel(2, 0), 0.7152f, 1e-6f);
  // Texel (i, j) is centred at ((i + 0.5) / W, (j + 0.5) / H).
  EXPECT_NEAR(t.height({1.5f / 3, 1.5f / 2}), 0.2126f, 1e-6f);
  EXPECT_NEAR(t.height({2.5f / 3, 0.5f / 2}), 0.7152f, 1e-6f);
  // Periodic: the last column blends with the first.
  EXPECT_NEAR(t.height({0.0f, 0.25f}), 0.5f * (t.texel(2, 0) + t.texel(0, 0)), 1e-6f);
  EXPECT_NEAR(t.height({1.0f + 2.5f / 3, 0.25f - 3.0f}), 0.7152f, 1e-5f);
  // Clamp-to-edge: the edge texel, no wrap.
  const HeightTable c(img, "rgba.png", HeightTableOptions{false});
  EXPECT_NEAR(c.height({0.999f, 0.25f}), 0.7152f, 1e-6f);
  EXPECT_NEAR(c.height({-5.0f, 0.25f}), 0.0f, 1e-6f);
}

TEST(HeightTable, HighestFrequency) {
  const int w = 64, h = 32;
  std::vector<float> t(w * h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      t[j * w + i] =
          std::sin(2 * kPi * 5 * (i + 0.5f) / w) + 0.5f * std::cos(2 * kPi * 3 * (j + 0.5f) / h);
  EXPECT_EQ(HeightTable(w, h, t).highestFrequency(), 5.0f);
  HeightTableOptions nyquist;
  nyquist.frequency = FrequencyEstimate::Nyquist;
  EXPECT_EQ(HeightTable(w, h, t, nyquist).highestFrequency(), 32.0f);
  EXPECT_EQ(HeightTable(4, 4, std::vector<float>(16, 2.0f)).highestFrequency(), 1.0f);  // flat
  // A wave along x only, with float rounding along y (a table computed by a band split): the
  // rounding is no detail along y.
  std::vector<float> alongX(w * h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      alongX[j * w + i] =
          0.3f * std::sin(2 * kPi * 3 * (i + 0.5f) / w) + 1e-8f * ((i * 7 + j * 13) % 5);
  EXPECT_EQ(HeightTable(w, h, alongX).highestFrequency(), 3.0f);
}

TEST_F(HeightTableFiles, LoadsExrAndPng) {
  Image img(4, 2, {"Y"});
  for (int x = 0; x < 4; ++x) img.at(x, 0, 0) = 0.25f * x;
  writeExr(dir_ / "h.exr", img);
  const HeightTable t = loadHeightTable(dir_ / "h.exr");
  EXPECT_EQ(t.width(), 4);
  EXPECT_EQ(t.heightTexels(), 2);
  EXPECT_FLOAT_EQ(t.texel(3, 1), 0.75f);
  Image rgb(2, 2, {"R", "G", "B"});
  for (float& v : rgb.pixels) v = 1.0f;
  writePngPreview(dir_ / "h.png", rgb);  // 8-bit: read back normalized to [0, 1]
  EXPECT_NEAR(loadHeightTable(dir_ / "h.png").texel(0, 0), 1.0f, 1e-6f);
}

TEST_F(HeightTableFiles, BadImagesNameTheFileAndTheProblem) {
  const fs::path missing = dir_ / "missing.png";
  EXPECT_HAS(errorOf([&] { loadHeightTable(missing); }), missing.string() + ": no such file");

  Image ok(64, 64, {"Y"});
  for (size_t i = 0; i < ok.pixels.size(); ++i) ok.pixels[i] = std::sin(0.37f * i);
  writeExr(dir_ / "cut.exr", ok);
  fs::resize_file(dir_ / "cut.exr", fs::file_size(dir_ / "cut.exr") / 2);
  EXPECT_HAS(errorOf([&] { loadHeightTable(dir_ / "cut.exr"); }),
             (dir_ / "cut.exr").string() + ": ");

  std::ofstream(dir_ / "junk.png") << "not an image at all";
  EXPECT_HAS(errorOf([&] { loadHeightTable(dir_ / "junk.png"); }),
             (dir_ / "junk.png").string() + ": ");

  Image empty(0, 4, {"Y"});
  EXPECT_HAS(errorOf([&] { HeightTable(empty, "zero.png"); }),
             "zero.png: height image has zero size (0x4)");

  Image five(2, 2, {"R", "G", "B", "A", "Z"});
  const std::string e5 = errorOf([&] { HeightTable(five, "five.exr"); });
  EXPECT_HAS(e5, "five.exr: height image has 5 channels");
  EXPECT_HAS(e5, "expected 1 (height), 2 (height and alpha), 3 (RGB) or 4 (RGBA)");

  Image nan(2, 2, {"Y"});
  nan.at(1, 0, 0) = NAN;
  EXPECT_HAS(errorOf([&] { HeightTable(nan, "nan.exr"); }),
             "nan.exr: height image has a NaN or infinite texel at (1, 0)");
}

}  // namespace
}  // namespace meso

namespace meso {
namespace {

// Alpha never changes the relief: grey + alpha and RGBA images give the heights of the same
// image without alpha (half-transparent and opaque texels alike), and say they ignored it; from a
// file too (OpenEXR keeps its channels as written).
TEST_F(HeightTableFiles, AlphaIsIgnoredAndReported) {
  Image grey(8, 8, {"Y"}), greyAlpha(8, 8, {"Y", "A"}), rgba(8, 8, {"R", "G", "B", "A"});
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const float h = 0.1f * x + 0.03f * y * y, a = (x + y) % 2 ? 0.5f : 1.0f;
      grey.at(x, y, 0) = h;
      greyAlpha.at(x, y, 0) = h, greyAlpha.at(x, y, 1) = a;
      for (int c = 0; c < 3; ++c) rgba.at(x, y, c) = h;
      rgba.at(x, y, 3) = a;
    }
  const HeightTable plain(grey, "grey.exr");
  EXPECT_FALSE(plain.ignoredAlpha());
  writeExr(dir_ / "rgba.exr", rgba);
  for (const HeightTable& t : {HeightTable(greyAlpha, "ya.exr"), HeightTable(rgba, "rgba.exr"),
                               loadHeightTable(dir_ / "rgba.exr")}) {
    EXPECT_TRUE(t.ignoredAlpha());
    ASSERT_EQ(t.texels().size(), plain.texels().size());
    for (size_t k = 0; k < t.texels().size(); ++k)
      EXPECT_NEAR(t.texels()[k], plain.texels()[k], 1e-6f);
    EXPECT_EQ(t.highestFrequency(), plain.highestFrequency());
  }
}

}  // namespace
}  // namespace meso
