// MESO_DCHECK compiled in, as in Debug builds and the sanitizer suite: this file turns it on
// whatever the build type.
#define MESO_ENABLE_DCHECK 1
#include "meso/core/check.h"

#include <gtest/gtest.h>

#include <vector>

namespace meso {
namespace {

int checkedAt(const std::vector<int>& v, int i) {
  MESO_DCHECK(i >= 0 && i < static_cast<int>(v.size()), "index in range");
  return v[static_cast<size_t>(i)];
}

TEST(DcheckDeathTest, FailedCheckAbortsNamingTheConditionAndTheMessage) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  static_assert(MESO_DCHECK_IS_ON);
  const std::vector<int> v{1, 2, 3};
  EXPECT_EQ(checkedAt(v, 2), 3);
  EXPECT_DEATH(checkedAt(v, 3),
               "check_test.cpp:[0-9]+: MESO_DCHECK\\(i >= 0 && i < "
               "static_cast<int>\\(v.size\\(\\)\\)\\) failed: index in range");
}

TEST(DcheckDeathTest, ConditionIsEvaluatedOnce) {
  int evaluations = 0;
  MESO_DCHECK(++evaluations == 1, "evaluated once");
  EXPECT_EQ(evaluations, 1);
}

}  // namespace
}  // namespace meso
