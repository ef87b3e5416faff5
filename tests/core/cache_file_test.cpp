// A cache file that fails a check is deleted with a warning naming it, why, and what the caller
// does instead; a missing file is a plain miss.
#include "meso/core/cache_file.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

namespace meso {
namespace {

namespace fs = std::filesystem;

struct TwoWords {
  uint32_t a, b;
};

class CacheFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("meso_cache_file_test_" +
            std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write(const std::string& bytes) {
    const fs::path file = dir_ / "entry.bin";
    std::ofstream(file, std::ios::binary) << bytes;
    return file;
  }
  fs::path dir_;
};

TEST_F(CacheFileTest, AMissingFileIsAMissWithoutAWarning) {
  std::string warning;
  CacheFileReader in(dir_ / "none.bin", "rebuilding", &warning);
  EXPECT_FALSE(in.opened());
  EXPECT_TRUE(warning.empty());
}

TEST_F(CacheFileTest, AWholeFileReadsToItsEnd) {
  const fs::path file = write(std::string("\x01\x00\x00\x00\x02\x00\x00\x00", 8));
  std::string warning;
  CacheFileReader in(file, "rebuilding", &warning);
  ASSERT_TRUE(in.opened());
  TwoWords h{};
  ASSERT_TRUE(in.readHeader(h));
  EXPECT_EQ(h.a, 1u);
  EXPECT_EQ(h.b, 2u);
  EXPECT_TRUE(in.atEnd());
  EXPECT_TRUE(warning.empty());
  EXPECT_TRUE(fs::exists(file));
}

TEST_F(CacheFileTest, ShortLongAndRejectedFilesAreDeletedWithTheirReason) {
  const auto rejected = [&](const std::string& bytes, const char* why, auto&& check) {
    const fs::path file = write(bytes);
    std::string warning;
    {
      CacheFileReader in(file, "re-rendering", &warning);
      ASSERT_TRUE(in.opened());
      check(in);
    }
    EXPECT_EQ(warning, file.string() + ": " + why + "; re-rendering");
    EXPECT_FALSE(fs::exists(file)) << why;
  };
  rejected("abc", "truncated header", [](CacheFileReader& in) {
    TwoWords h{};
    EXPECT_FALSE(in.readHeader(h));
  });
  rejected(std::string(9, 'x'), "trailing bytes", [](CacheFileReader& in) {
    TwoWords h{};
    ASSERT_TRUE(in.readHeader(h));
    EXPECT_FALSE(in.atEnd());
  });
  rejected(std::string(8, 'x'), "key mismatch", [](CacheFileReader& in) {
    TwoWords h{};
    ASSERT_TRUE(in.readHeader(h));
    const std::optional<int> none = in.reject("key mismatch");
    EXPECT_FALSE(none.has_value());
  });
}

}  // namespace
}  // namespace meso
