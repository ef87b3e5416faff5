// Vector types and small helpers on GLM shared by every area.
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <numbers>

namespace meso {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using Vec4 = glm::vec4;
using Mat4 = glm::mat4;

inline constexpr float kPi = std::numbers::pi_v<float>;

inline float radians(float degrees) { return degrees * (kPi / 180.0f); }
inline float degrees(float radians) { return radians * (180.0f / kPi); }

// True when every component is finite (no NaN, no Inf).
inline bool isFinite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace meso
