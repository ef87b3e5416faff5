#include "meso/appearance/table_cache.h"

#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <fstream>

namespace meso {
namespace {

namespace fs = std::filesystem;

class TableCacheTest : public meso::testing::TempDirTest {
 protected:
  std::vector<float> data_{1.0f, 2.5f, -3.0f, 1e-7f};
};

TEST_F(TableCacheTest, SecondLoadIsAHitWithTheSameBits) {
  const TableCache cache(dir_);
  std::string warning;
  EXPECT_FALSE(cache.load(42, &warning).has_value());
  cache.store(42, data_, &warning);
  EXPECT_TRUE(warning.empty()) << warning;
  const auto back = cache.load(42, &warning);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(*back, data_);
  EXPECT_FALSE(cache.load(43, &warning).has_value());
}

TEST_F(TableCacheTest, CorruptTruncatedAndStaleFilesAreRejectedAndRemoved) {
  const TableCache cache(dir_);
  std::string warning;
  cache.store(7, data_, &warning);
  const fs::path file = cache.fileFor(7);
  {  // flip one payload byte
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(-2, std::ios::end);
    f.put('\x55');
  }
  EXPECT_FALSE(cache.load(7, &warning).has_value());
  EXPECT_NE(warning.find("checksum mismatch"), std::string::npos) << warning;
  EXPECT_FALSE(fs::exists(file));

  cache.store(7, data_, &warning);
  fs::resize_file(file, fs::file_size(file) - 3);
  EXPECT_FALSE(cache.load(7, &warning).has_value());
  EXPECT_NE(warning.find("truncated"), std::string::npos) << warning;

  std::ofstream(file, std::ios::binary)
      << "garbage that is long enough to fill a header, surely it is";
  EXPECT_FALSE(cache.load(7, &warning).has_value());
  EXPECT_NE(warning.find("not a meso table file"), std::string::npos) << warning;
}

TEST_F(TableCacheTest, EmptyFolderDisablesTheCache) {
  const TableCache cache{fs::path()};
  std::string warning;
  cache.store(1, data_, &warning);
  EXPECT_FALSE(cache.load(1, &warning).has_value());
}

TEST(Hasher, DistinguishesInputs) {
  EXPECT_NE(Hasher().value(1.0f).digest(), Hasher().value(1.0000001f).digest());
  EXPECT_NE(Hasher().string("ab").string("c").digest(), Hasher().string("a").string("bc").digest());
  EXPECT_EQ(Hasher().value(3).digest(), Hasher().value(3).digest());
}

}  // namespace
}  // namespace meso
