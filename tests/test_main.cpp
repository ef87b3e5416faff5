// The test programs' main: the floating-point mode of every meso program (core/floating_point.h)
// before any test runs, then GoogleTest.
#include "meso/core/floating_point.h"

#include <gtest/gtest.h>

int main(int argc, char** argv) {
  meso::useFlushToZero();
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
