// TransitionsFor::Offsets against TransitionsFor::Geometry at one point: what the tessellator's
// offsets read (ReliefDisplacement::offset) must be the same bits.
#pragma once

#include "meso/render/transition.h"

#include <gtest/gtest.h>

#include <string>

namespace meso::testing {

// Counts, T, disp and heights of the raised levels, and every frame the offsets read: frames[i] of
// each level i, and the slopes of every raised level but the last one.
inline void expectOffsetsAgree(const LevelTransitions& offsets, const LevelTransitions& geometry,
                               const std::string& where) {
  ASSERT_EQ(offsets.count, geometry.count) << where;
  ASSERT_EQ(offsets.raised, geometry.raised) << where;
  for (int i = 0; i < geometry.count; ++i) {
    EXPECT_EQ(offsets.T[i], geometry.T[i]) << where << " level " << i;
    EXPECT_EQ(offsets.disp[i], geometry.disp[i]) << where << " level " << i;
    EXPECT_EQ(offsets.frames[i].N, geometry.frames[i].N) << where << " level " << i;
    EXPECT_EQ(offsets.frames[i].Pu, geometry.frames[i].Pu) << where << " level " << i;
    EXPECT_EQ(offsets.frames[i].Pv, geometry.frames[i].Pv) << where << " level " << i;
  }
  for (int i = 0; i < geometry.raised; ++i) {
    EXPECT_EQ(offsets.H[i], geometry.H[i]) << where << " level " << i;
    if (i + 1 < geometry.count) {
      EXPECT_EQ(offsets.B[i], geometry.B[i]) << where << " level " << i;
    }
  }
}

}  // namespace meso::testing
