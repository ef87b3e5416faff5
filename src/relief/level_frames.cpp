// Becker & Max 1993, section 2.3: P_u[level + 1] = P_u[level] + B_u[level] N[level].
#include "meso/relief/level_frames.h"

#include "meso/relief/blinn_normal.h"

#include <cmath>
#include <stdexcept>

namespace meso {

namespace {

constexpr float kMaxSlope = 1e15f;

// The unit direction displacement follows: N, else P_u x P_v, else +z.
Vec3 unitNormal(const SurfaceFrame& f) {
  if (std::abs(glm::dot(f.N, f.N) - 1.0f) < 1e-6f) return f.N;  // unit already (to 5e-7)
  for (const Vec3& v : {f.N, glm::cross(f.Pu, f.Pv)}) {
    const float len = glm::length(v);
    if (len > 1e-30f && std::isfinite(len)) return v / len;
  }
  return Vec3(0.0f, 0.0f, 1.0f);
}

}  // namespace

SurfaceFrame nextFrame(const SurfaceFrame& frame, Vec2 B) {
  if (!std::isfinite(B.x) || !std::isfinite(B.y)) B = Vec2(0.0f);
  // The normal is tangential long before this; the clamp keeps the tangents finite for 8 levels.
  B = glm::clamp(B, Vec2(-kMaxSlope), Vec2(kMaxSlope));
  const Vec3 n = unitNormal(frame);
  // P'_u x P'_v of these tangents is exactly the Blinn normal's direction (n x n = 0).
  return {frame.Pu + B.x * n, frame.Pv + B.y * n, blinnNormal(frame.Pu, frame.Pv, n, B.x, B.y)};
}

LevelFrames levelFrames(const SurfaceFrame& limit, std::span<const Vec2> B) {
  if (B.size() > static_cast<size_t>(kMaxReliefLevels))
    throw std::length_error("levelFrames: more than kMaxReliefLevels relief levels");
  LevelFrames out;
  out.count = static_cast<int>(B.size());
  out.frames[0] = limit;
  for (int i = 0; i < out.count; ++i) {
    out.B[i] = B[i];
    out.frames[i + 1] = nextFrame(out.frames[i], B[i]);
  }
  return out;
}

LevelFrames levelFrames(const SurfaceFrame& limit, std::span<const HeightLevel> levels, Vec2 uv) {
  if (levels.size() > static_cast<size_t>(kMaxReliefLevels))
    throw std::length_error("levelFrames: more than kMaxReliefLevels relief levels");
  std::array<Vec2, kMaxReliefLevels> B;
  for (size_t i = 0; i < levels.size(); ++i) B[i] = levels[i].derivatives(uv);
  return levelFrames(limit, std::span<const Vec2>(B.data(), levels.size()));
}

}  // namespace meso
