#include "meso/appearance/table_cache.h"

#include "support/temp_dir.h"

#include "meso/core/error.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <thread>

namespace meso {
namespace {

namespace fs = std::filesystem;

class TableCacheTest : public meso::testing::TempDirTest {
 protected:
  std::vector<float> data_{1.0f, 2.5f, -3.0f, 1e-7f};
  // Stores data_ under `key` and dates its last use `age` ago.
  void storeUsed(const TableCache& cache, uint64_t key, std::chrono::minutes age) {
    std::string warning;
    cache.store(key, data_, &warning);
    ASSERT_TRUE(warning.empty()) << warning;
    fs::last_write_time(cache.fileFor(key), fs::file_time_type::clock::now() - age);
  }
};

// A value of MESO_CACHE_LIMIT for one test, restored afterwards.
class ScopedLimitVariable {
 public:
  explicit ScopedLimitVariable(const char* value) {
    if (const char* old = std::getenv("MESO_CACHE_LIMIT")) old_ = old;
    if (value)
      setenv("MESO_CACHE_LIMIT", value, 1);
    else
      unsetenv("MESO_CACHE_LIMIT");
  }
  ~ScopedLimitVariable() {
    if (old_)
      setenv("MESO_CACHE_LIMIT", old_->c_str(), 1);
    else
      unsetenv("MESO_CACHE_LIMIT");
  }

 private:
  std::optional<std::string> old_;
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

// Two builders of one key, each with its own TableCache (and so its own lock file descriptor, as
// two processes have): the second waits for the first's lock, then loads what it stored.
TEST_F(TableCacheTest, TwoBuildersOfOneKeyBuildItOnce) {
  std::atomic<int> builds{0};
  const auto slowBuild = [&] {
    ++builds;
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    return data_;
  };
  std::vector<float> results[2];
  bool built[2] = {false, false};
  Warnings warnings[2];
  std::atomic<int> ready{0};
  const auto builder = [&](int i) {
    const TableCache cache(dir_);
    ++ready;
    while (ready.load() < 2) std::this_thread::yield();
    results[i] = cache.loadOrBuild(99, slowBuild, &warnings[i], &built[i]);
  };
  std::thread first(builder, 0), second(builder, 1);
  first.join();
  second.join();
  EXPECT_EQ(builds.load(), 1);
  EXPECT_NE(built[0], built[1]);
  EXPECT_EQ(results[0], data_);
  EXPECT_EQ(results[1], data_);
  EXPECT_TRUE(warnings[0].empty() && warnings[1].empty());
  EXPECT_TRUE(fs::exists(TableCache(dir_).lockFileFor(99)));  // it may stay
  // Later builders of the key load it.
  bool again = true;
  EXPECT_EQ(TableCache(dir_).loadOrBuild(99, slowBuild, nullptr, &again), data_);
  EXPECT_FALSE(again);
  EXPECT_EQ(builds.load(), 1);
}

// A lock holds until released: a second object's try in prune() sees it busy.
TEST_F(TableCacheTest, PruneKeepsTablesLockedElsewhere) {
  const TableCache cache(dir_, uint64_t{1} << 40);
  storeUsed(cache, 1, std::chrono::minutes(30));
  storeUsed(cache, 2, std::chrono::minutes(20));
  TableCache::Lock held = TableCache(dir_).lock(1);
  ASSERT_TRUE(held.held());
  TableCacheRemoval r = cache.prune(0);
  EXPECT_EQ(r.removed, 1);
  EXPECT_EQ(r.kept, 1);
  EXPECT_TRUE(fs::exists(cache.fileFor(1)));
  EXPECT_FALSE(fs::exists(cache.fileFor(2)));
  held.unlock();
  r = cache.prune(0);
  EXPECT_EQ(r.removed, 1);
  EXPECT_EQ(r.bytesLeft, 0u);
  EXPECT_FALSE(fs::exists(cache.fileFor(1)));
}

TEST_F(TableCacheTest, LockIsANoOpWhenTheCacheIsDisabledOrUnwritable) {
  EXPECT_FALSE(TableCache(fs::path()).lock(1).held());
  const fs::path notAFolder = write("file", "x");
  const TableCache unwritable(notAFolder / "cache");
  EXPECT_FALSE(unwritable.lock(1).held());
  // Both still build, every time.
  Warnings warnings;
  bool built = false;
  EXPECT_EQ(unwritable.loadOrBuild(
                1, [&] { return data_; }, &warnings, &built),
            data_);
  EXPECT_TRUE(built);
  EXPECT_EQ(warnings.size(), 1u);  // the store failed
  EXPECT_EQ(TableCache(fs::path())
                .loadOrBuild(
                    1, [&] { return data_; }, nullptr, &built),
            data_);
  EXPECT_TRUE(built);
}

TEST_F(TableCacheTest, LoadOrBuildRebuildsCorruptTruncatedAndForeignFiles) {
  const TableCache cache(dir_);
  const fs::path file = cache.fileFor(5);
  const auto rebuilds = [&](const char* why) {
    Warnings warnings;
    bool built = false;
    EXPECT_EQ(cache.loadOrBuild(
                  5, [&] { return data_; }, &warnings, &built),
              data_)
        << why;
    EXPECT_TRUE(built) << why;
    ASSERT_EQ(warnings.size(), 1u) << why;
    const std::string warning0 = warnings.list()[0];
    EXPECT_NE(warning0.find(why), std::string::npos) << warning0;
    std::string warning;
    EXPECT_EQ(cache.load(5, &warning), data_) << why;  // stored again, whole
  };
  cache.store(5, data_, nullptr);
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(-1, std::ios::end);
    f.put('\x7f');
  }
  rebuilds("checksum mismatch");
  fs::resize_file(file, fs::file_size(file) - 5);
  rebuilds("truncated");
  std::ofstream(file, std::ios::binary) << "a PNG, a text file, anything that is not a table here";
  rebuilds("not a meso table file");
}

// Eviction after a store goes by last use (mtime, which a hit refreshes), oldest first, and
// spares the table just stored, subfolders and files that are not tables.
TEST_F(TableCacheTest, StoreEvictsLeastRecentlyUsedTablesOverTheLimit) {
  const uint64_t bytes = [&] {
    TableCache(dir_, 0).store(1, data_, nullptr);
    return fs::file_size(TableCache(dir_, 0).fileFor(1));
  }();
  const TableCache cache(dir_, 3 * bytes);
  storeUsed(cache, 1, std::chrono::minutes(60));
  storeUsed(cache, 2, std::chrono::minutes(180));
  storeUsed(cache, 3, std::chrono::minutes(120));
  fs::create_directories(dir_ / "references");
  write("references/0000000000000002.tbl", std::string(100, 'r'));
  write("notes.txt", "kept");
  write(".0000000000000007.tmp-1-0.tbl", "a store in progress");
  std::string warning;
  cache.store(4, data_, &warning);
  EXPECT_TRUE(warning.empty()) << warning;
  EXPECT_FALSE(fs::exists(cache.fileFor(2)));  // the oldest
  for (uint64_t k : {1, 3, 4}) EXPECT_TRUE(fs::exists(cache.fileFor(k))) << k;
  // A hit makes key 3 the most recent: key 1 goes next.
  EXPECT_TRUE(cache.load(3, &warning).has_value());
  cache.store(5, data_, &warning);
  EXPECT_FALSE(fs::exists(cache.fileFor(1)));
  for (uint64_t k : {3, 4, 5}) EXPECT_TRUE(fs::exists(cache.fileFor(k))) << k;
  // A limit below one table keeps only the table just stored.
  const TableCache tiny(dir_, bytes / 2);
  tiny.store(6, data_, &warning);
  ASSERT_EQ(tiny.entries().size(), 1u);
  EXPECT_EQ(tiny.entries()[0].key, 6u);
  EXPECT_TRUE(fs::exists(dir_ / "references/0000000000000002.tbl"));
  EXPECT_TRUE(fs::exists(dir_ / "notes.txt"));
  EXPECT_TRUE(fs::exists(dir_ / ".0000000000000007.tmp-1-0.tbl"));
}

TEST_F(TableCacheTest, ListPruneAndClear) {
  const TableCache cache(dir_, uint64_t{1} << 40);
  EXPECT_TRUE(cache.entries().empty());
  EXPECT_TRUE(TableCache(dir_ / "missing").entries().empty());
  storeUsed(cache, 0xa, std::chrono::minutes(5));
  storeUsed(cache, 0xb, std::chrono::minutes(50));
  storeUsed(cache, 0xc, std::chrono::minutes(15));
  write("notes.txt", "kept");
  fs::create_directories(dir_ / "references");
  const std::vector<TableCacheEntry> entries = cache.entries();
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(entries[0].key, 0xbu);  // least recently used first
  EXPECT_EQ(entries[1].key, 0xcu);
  EXPECT_EQ(entries[2].key, 0xau);
  EXPECT_EQ(entries[0].file.filename(), "000000000000000b.tbl");
  const uint64_t bytes = entries[0].bytes;
  EXPECT_EQ(bytes, fs::file_size(cache.fileFor(0xb)));
  // Prune to two tables: the oldest goes.
  TableCacheRemoval r = cache.prune(2 * bytes + 1);
  EXPECT_EQ(r.removed, 1);
  EXPECT_EQ(r.bytesFreed, bytes);
  EXPECT_EQ(r.bytesLeft, 2 * bytes);
  EXPECT_FALSE(fs::exists(cache.fileFor(0xb)));
  r = cache.prune(2 * bytes);  // already within
  EXPECT_EQ(r.removed, 0);
  // Clear: every table and lock file, nothing else.
  cache.lock(0xa).unlock();
  ASSERT_TRUE(fs::exists(cache.lockFileFor(0xa)));
  r = cache.clear();
  EXPECT_EQ(r.removed, 2);
  EXPECT_EQ(r.bytesFreed, 2 * bytes);
  EXPECT_EQ(r.locksRemoved, 1);
  EXPECT_EQ(r.kept, 0);
  EXPECT_TRUE(cache.entries().empty());
  EXPECT_FALSE(fs::exists(cache.lockFileFor(0xa)));
  EXPECT_TRUE(fs::exists(dir_ / "notes.txt"));
  EXPECT_TRUE(fs::exists(dir_ / "references"));
}

TEST(TableCacheLimit, ParsesBytesWithSuffixes) {
  EXPECT_EQ(parseByteSize("0", "x"), 0u);
  EXPECT_EQ(parseByteSize("1234", "x"), 1234u);
  EXPECT_EQ(parseByteSize("1234B", "x"), 1234u);
  EXPECT_EQ(parseByteSize("500K", "x"), 500u << 10);
  EXPECT_EQ(parseByteSize("500M", "x"), 500u << 20);
  EXPECT_EQ(parseByteSize("500m", "x"), 500u << 20);
  EXPECT_EQ(parseByteSize("4G", "x"), uint64_t{4} << 30);
  EXPECT_EQ(parseByteSize("4GiB", "x"), uint64_t{4} << 30);
  EXPECT_EQ(parseByteSize("4gb", "x"), uint64_t{4} << 30);
  EXPECT_EQ(parseByteSize("2T", "x"), uint64_t{2} << 40);
  EXPECT_EQ(parseByteSize("18446744073709551615", "x"), ~uint64_t{0});
  for (const char* bad : {"", "G", "abc", "-1", "+5", "1.5G", " 4G", "4G ", "4 G", "4X", "4iB",
                          "4GG", "4KB2", "18446744073709551616", "17179869184G"}) {
    try {
      parseByteSize(bad, "MESO_CACHE_LIMIT");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("MESO_CACHE_LIMIT: expected a size in bytes"), std::string::npos)
          << message;
      EXPECT_NE(message.find("'" + std::string(bad) + "'"), std::string::npos) << message;
    }
  }
}

TEST(TableCacheLimit, DefaultLimitComesFromTheEnvironment) {
  {
    const ScopedLimitVariable unset(nullptr);
    EXPECT_EQ(TableCache::defaultLimit(), kDefaultTableCacheLimit);
    EXPECT_EQ(kDefaultTableCacheLimit, uint64_t{4} << 30);
    EXPECT_EQ(TableCache("/tmp/anywhere").limit(), kDefaultTableCacheLimit);
  }
  {
    const ScopedLimitVariable set("300M");
    EXPECT_EQ(TableCache::defaultLimit(), uint64_t{300} << 20);
    EXPECT_EQ(TableCache("/tmp/anywhere").limit(), uint64_t{300} << 20);
  }
  {
    const ScopedLimitVariable bad("lots");
    EXPECT_THROW(TableCache::defaultLimit(), Error);
    EXPECT_THROW(TableCache{"/tmp/anywhere"}, Error);
    // A disabled cache has no use for a limit. (Braces: `TableCache(fs::path())` alone is a
    // declaration to clang.)
    EXPECT_NO_THROW(TableCache{fs::path()});
  }
}

TEST(TableCacheLimit, FormatsSizes) {
  EXPECT_EQ(formatByteSize(0), "0 B");
  EXPECT_EQ(formatByteSize(1023), "1023 B");
  EXPECT_EQ(formatByteSize(1536), "1.5 KiB");
  EXPECT_EQ(formatByteSize(uint64_t{4} << 30), "4.0 GiB");
}

TEST(Hasher, DistinguishesInputs) {
  EXPECT_NE(Hasher().value(1.0f).digest(), Hasher().value(1.0000001f).digest());
  EXPECT_NE(Hasher().string("ab").string("c").digest(), Hasher().string("a").string("bc").digest());
  EXPECT_EQ(Hasher().value(3).digest(), Hasher().value(3).digest());
}

}  // namespace
}  // namespace meso
