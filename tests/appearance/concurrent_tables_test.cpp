// A material's table sets are built at once (classes, levels, the tiles classes derive from):
// the same bits for any thread count, and one build per table when builders share a cache.
#include "meso/appearance/material_tables.h"

#include "support/small_tables.h"

#include <gtest/gtest.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <filesystem>

namespace meso {
namespace {

namespace fs = std::filesystem;

Material twoLevels() { return testing::twoNoiseLevels("two"); }

TableSettings smallSettings() { return testing::smallTableSettings(6); }

// Three classes: two lengths of the isotropic shape and a stretched one (derived from a tile).
std::vector<MetricClass> threeClasses() {
  return {{1.0f, MetricShape{}}, {2.0f, MetricShape{}}, {1.4f, MetricShape{2.0f, 0.0f}}};
}

MaterialRelief buildWith(int threads, const TableCache& cache) {
  tbb::task_arena arena(threads);
  return arena.execute([&] {
    return buildMaterialRelief(twoLevels(), cache, nullptr, smallSettings(), threeClasses());
  });
}

TEST(ConcurrentTables, SameBitsForOneAndTwoThreads) {
  const TableCache none{fs::path()};
  const MaterialRelief one = buildWith(1, none), two = buildWith(2, none);
  ASSERT_EQ(one.metrics.size(), 3u);
  ASSERT_EQ(two.metrics.size(), 3u);
  for (size_t c = 0; c < 3; ++c) {
    ASSERT_EQ(one.metrics[c].levels.size(), 2u);
    for (size_t l = 0; l < 2; ++l) {
      const LevelTables& a = one.metrics[c].levels[l];
      const LevelTables& b = two.metrics[c].levels[l];
      EXPECT_EQ(a.key, b.key);
      EXPECT_EQ(a.brdf.data(), b.brdf.data()) << "class " << c << " level " << l;
      EXPECT_EQ(a.shadowing.toData(), b.shadowing.toData()) << "class " << c << " level " << l;
      EXPECT_FALSE(a.shadowing.empty());
    }
  }
  // Non-vacuity: the classes' and levels' tables differ from each other.
  EXPECT_NE(one.metrics[0].levels[0].brdf.data(), one.metrics[0].levels[1].brdf.data());
  EXPECT_NE(one.metrics[0].levels[0].brdf.data(), one.metrics[2].levels[0].brdf.data());
}

// Two builders of the same material in one process, at once, on one cache folder: each table is
// built once (the other waits for its lock, then loads it), and neither waits forever.
TEST(ConcurrentTables, TwoBuildersShareEachBuild) {
  const fs::path folder = fs::path(::testing::TempDir()) / "meso_concurrent_tables";
  fs::remove_all(folder);
  const TableCache cache{folder};
  MaterialRelief a, b;
  tbb::task_arena arena(2);
  arena.execute([&] {
    tbb::parallel_invoke(
        [&] {
          a = buildMaterialRelief(twoLevels(), cache, nullptr, smallSettings(), threeClasses());
        },
        [&] {
          b = buildMaterialRelief(twoLevels(), cache, nullptr, smallSettings(), threeClasses());
        });
  });
  EXPECT_EQ(a.tablesBuilt + a.tablesFromCache, 6);
  EXPECT_EQ(b.tablesBuilt + b.tablesFromCache, 6);
  EXPECT_EQ(a.tablesBuilt + b.tablesBuilt, 6);  // every set built by one of them
  for (size_t c = 0; c < 3; ++c)
    for (size_t l = 0; l < 2; ++l)
      EXPECT_EQ(a.metrics[c].levels[l].brdf.data(), b.metrics[c].levels[l].brdf.data());
  fs::remove_all(folder);
}

}  // namespace
}  // namespace meso
