#include "meso/core/floating_point.h"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>

namespace meso {
namespace {

// A denormal product, computed where the compiler cannot fold it.
float denormalProduct() {
  volatile float a = 1e-30f, b = 1e-10f;
  return a * b;
}

TEST(FloatingPoint, TheTestProgramRunsInMesosMode) {
#if defined(__SSE2__)
  EXPECT_TRUE(flushesToZero());
  EXPECT_EQ(denormalProduct(), 0.0f);  // 1e-40 is a denormal: flushed
#else
  GTEST_SKIP() << "no SSE: the mode is the default one";
#endif
}

// Every task of a parallel loop runs in the main thread's mode, on whatever thread it runs: the
// reason a table or an image has the same bits for any thread count.
TEST(FloatingPoint, TasksOnEveryThreadInheritTheMode) {
#if defined(__SSE2__)
  std::atomic<int> flushing{0}, denormal{0};
  tbb::task_arena arena(2);
  arena.execute([&] {
    tbb::parallel_for(0, 64, [&](int) {
      flushing += flushesToZero() ? 1 : 0;
      denormal += denormalProduct() != 0.0f ? 1 : 0;
    });
  });
  EXPECT_EQ(flushing.load(), 64);
  EXPECT_EQ(denormal.load(), 0);
#else
  GTEST_SKIP() << "no SSE";
#endif
}

}  // namespace
}  // namespace meso
