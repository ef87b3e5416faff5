// Becker & Max 1993, section 2.3: frames of stacked levels, P_u[i + 1] = P_u[i] + B_u[i] N[i].
#pragma once

#include "meso/core/math.h"
#include "meso/relief/height_source.h"

#include <array>
#include <span>

namespace meso {

inline constexpr int kMaxReliefLevels = 8;

// A surface frame: tangents P_u, P_v (any lengths and angle) and the unit normal N.
struct SurfaceFrame {
  Vec3 Pu, Pv, N;
};

// frames[0] is the limit surface's frame; frames[i] (1 <= i <= count) is the frame after levels
// 1..i are applied, i.e. the surface level i + 1 perturbs. B[i] = (B_u, B_v) of level i + 1.
struct LevelFrames {
  int count = 0;
  std::array<SurfaceFrame, kMaxReliefLevels + 1> frames{};
  std::array<Vec2, kMaxReliefLevels> B{};
};

// One level: P'_u = P_u + B_u N, P'_v = P_v + B_v N, N' = blinnNormal(P_u, P_v, N, B_u, B_v)
// (which is exactly normalize(P'_u x P'_v), oriented like N). Non-finite B counts as 0 and |B| is
// clamped to 1e15, so frames stay finite.
SurfaceFrame nextFrame(const SurfaceFrame& frame, Vec2 B);

// All levels from their derivatives (B_u, B_v). No allocation. Throws std::length_error for more
// than kMaxReliefLevels levels (scene input is checked long before this).
LevelFrames levelFrames(const SurfaceFrame& limit, std::span<const Vec2> B);
// All levels at surface parameters uv: B of level i is levels[i].derivatives(uv).
LevelFrames levelFrames(const SurfaceFrame& limit, std::span<const HeightLevel> levels, Vec2 uv);

}  // namespace meso
