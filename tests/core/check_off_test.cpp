// MESO_DCHECK compiled out, as in Release builds: this file turns it off whatever the build type.
#include <gtest/gtest.h>

#undef MESO_ENABLE_DCHECK
#ifndef NDEBUG
#define NDEBUG
#endif
#include "meso/core/check.h"

namespace meso {
namespace {

TEST(DcheckOff, ConditionIsNeitherEvaluatedNorFatal) {
  static_assert(!MESO_DCHECK_IS_ON);
  int evaluations = 0;
  MESO_DCHECK(++evaluations > 5, "would fail");
  EXPECT_EQ(evaluations, 0);
}

}  // namespace
}  // namespace meso
