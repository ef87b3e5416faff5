#include "meso/core/error.h"
#include "meso/core/image_io.h"
#include "meso/core/image_io_memory.h"

#include "support/temp_dir.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace meso {
namespace {

namespace fs = std::filesystem;

class ImageIoTest : public testing::TempDirTest {
 protected:
};

Image testImage() {
  Image img(5, 3, {"R", "G", "B", "depth.Z", "normal.X", "normal.Y", "normal.Z"});
  for (size_t i = 0; i < img.pixels.size(); ++i)
    img.pixels[i] = 0.37f * static_cast<float>(i) - 3.1f;
  return img;
}

TEST_F(ImageIoTest, ExrRoundTripKeepsEveryLayerBitExact) {
  const Image img = testImage();
  writeExr(dir_ / "a.exr", img);
  const Image back = readImage(dir_ / "a.exr");
  ASSERT_EQ(back.width, img.width);
  ASSERT_EQ(back.height, img.height);
  ASSERT_EQ(back.numChannels(), img.numChannels());
  for (int c = 0; c < img.numChannels(); ++c) {
    const int bc = back.channelIndex(img.channels[c]);
    ASSERT_GE(bc, 0) << img.channels[c];
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) EXPECT_EQ(back.at(x, y, bc), img.at(x, y, c));
  }
}

// Frames are written with OpenEXR's thread pool as `--threads` sets it: many blocks of 16 rows,
// compressed on 1 or 3 threads, give the same bytes, which read back bit for bit.
TEST_F(ImageIoTest, ExrBytesAreTheSameWhateverTheThreads) {
  Image img(64, 100, {"R", "G", "B", "depth.Z"});
  for (size_t i = 0; i < img.pixels.size(); ++i)
    img.pixels[i] = std::sin(0.01f * static_cast<float>(i)) * static_cast<float>(i % 7);
  std::string bytes[2];
  for (const int threads : {1, 3}) {
    setImageThreads(threads);
    int n = -1;
    ASSERT_TRUE(OIIO::getattribute("exr_threads", n));
    EXPECT_EQ(n, threads);
    bytes[threads == 3] = encodeExr(img);
  }
  setImageThreads(0);
  EXPECT_EQ(bytes[0], bytes[1]);
  const Image back = readImageFromMemory(bytes[1].data(), bytes[1].size(), "t.exr");
  ASSERT_EQ(back.pixels.size(), img.pixels.size());
  for (size_t i = 0; i < img.pixels.size(); ++i) ASSERT_EQ(back.pixels[i], img.pixels[i]) << i;
}

TEST_F(ImageIoTest, PngPreviewIsSrgbEncoded) {
  Image img(4, 1, {"R", "G", "B"});
  const float linear[4] = {0.0f, 0.2140f, 0.5f, 2.0f};
  for (int x = 0; x < 4; ++x)
    for (int c = 0; c < 3; ++c) img.at(x, 0, c) = linear[x];
  writePngPreview(dir_ / "a.png", img);
  const Image back = readImage(dir_ / "a.png");
  ASSERT_EQ(back.numChannels(), 3);
  // sRGB(0.214) = 0.5; sRGB(0.5) = 0.7354; values above 1 clamp to 1.
  EXPECT_NEAR(back.at(0, 0, 0), 0.0f, 1e-6f);
  EXPECT_NEAR(back.at(1, 0, 1), 0.5f, 1.0f / 255.0f);
  EXPECT_NEAR(back.at(2, 0, 2), 0.7354f, 1.0f / 255.0f);
  EXPECT_NEAR(back.at(3, 0, 0), 1.0f, 1e-6f);
}

TEST_F(ImageIoTest, NoTemporaryFileIsLeftBehind) {
  writeExr(dir_ / "a.exr", testImage());
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir_)) {
    ++files;
    EXPECT_EQ(e.path().filename(), "a.exr");
  }
  EXPECT_EQ(files, 1);
}

TEST_F(ImageIoTest, FailedWriteLeavesNoFile) {
  const fs::path target = dir_ / "missing_folder" / "a.exr";
  EXPECT_THROW(writeExr(target, testImage()), Error);
  EXPECT_FALSE(fs::exists(target));
}

TEST_F(ImageIoTest, MissingAndCorruptFilesAreClearErrors) {
  try {
    readImage(dir_ / "nope.png");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("nope.png: no such file"), std::string::npos) << e.what();
  }
  std::ofstream(dir_ / "garbage.png") << "this is not a png";
  EXPECT_THROW(readImage(dir_ / "garbage.png"), Error);
  // A truncated EXR: the header survives, the pixels do not.
  writeExr(dir_ / "t.exr", testImage());
  fs::resize_file(dir_ / "t.exr", fs::file_size(dir_ / "t.exr") / 2);
  EXPECT_THROW(readImage(dir_ / "t.exr"), Error);
}

// A 144-byte OpenEXR header (found by fuzz_height_image) whose channel list ends before its
// declared size: OpenEXR reads the next attribute from inside that value, finds an attribute of
// 939 MB there and allocates it. The framing check follows OpenEXR's reading and refuses it.
TEST_F(ImageIoTest, ExrAttributeSizesAreCheckedAsOpenExrReadsThem) {
  const std::string corrupt(
      "\x76\x2f\x31\x01\x02\x00\x00\x00\x45\x70\x69\x66\x3a\x49\x6d\x3b\x00\x73\x74\x72\x69\x6e"
      "\x67\x00\x13\x00\x00\x00\x32\x30\x32\x35\x3a\x31\x31\x3a\x32\x33\x20\x30\x32\x3a\x32\x34"
      "\x3a\x31\x32\x63\x68\x61\x6e\x6e\x65\x6c\x73\x00\x63\x68\x6c\x69\x73\x74\x00\x13\x00\x00"
      "\x00\x00\x01\x00\x9d\x00\x03\x64\x61\x74\x61\x57\x69\x6e\x64\x6f\x77\x00\x62\x6f\x78\x32"
      "\x69\x00\x10\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00"
      "\x00\xfc\xff\xff\xff\xff\xff\xff\xff\x00\x00\x00\x00\x00\x00\x10\x00\x00\x00\x00\x6f\x77"
      "\x00\x62\x6f\x78\x34\x69\x00\x10\x00\x00\x38\xb5\x38",
      145);
  try {
    readImageFromMemory(corrupt.data(), corrupt.size(), "corrupt.exr");
    FAIL() << "read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("corrupt.exr: truncated or corrupt OpenEXR header: "
                                         "attribute \"channels\" of type chlist declares 19 bytes"),
              std::string::npos)
        << e.what();
  }
  // meso's own EXR passes the check and reads back.
  writeExr(dir_ / "ok.exr", testImage());
  std::ifstream in(dir_ / "ok.exr", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(readImageFromMemory(bytes.data(), bytes.size(), "ok.exr").pixels, testImage().pixels);
}

}  // namespace
}  // namespace meso
