// Vector types and small helpers on GLM shared by every area.
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <numbers>

namespace meso {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using Vec4 = glm::vec4;
using Mat3 = glm::mat3;
using Mat4 = glm::mat4;

inline constexpr float kPi = std::numbers::pi_v<float>;

inline float radians(float degrees) { return degrees * (kPi / 180.0f); }
inline float degrees(float radians) { return radians * (180.0f / kPi); }

// Rec. 709 luminance of linear RGB.
inline float luminance(const Vec3& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

// True when every component is finite (no NaN, no Inf).
inline bool isFinite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The z component of the cross product of two plane vectors (twice the signed area they span).
inline float cross2(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }

// Distance from p to the box [lo, hi] (0 inside).
inline float boxDistance(Vec3 p, Vec3 lo, Vec3 hi) {
  return glm::length(glm::max(glm::max(lo - p, p - hi), Vec3(0.0f)));
}

// acos and atan2 for the pixel loop's table lookups (redistribution, BRDF and self-shadowing
// angles): polynomials (Abramowitz & Stegun 4.4.46 and 4.4.49, |error| <= 2e-8 rad in exact
// arithmetic, below 1e-6 rad in float: tests/core/fast_math_test.cpp) instead of libm's calls,
// which were 14% of a scenes/torus_floor.toml frame. Table bins are 1e-2 rad wide or more. NaN
// stays NaN; arguments outside [-1, 1] are clamped; fastAtan2 of zeros and infinities is
// std::atan2's.
inline float fastAcos(float x) {
  x = x < -1.0f ? -1.0f : x > 1.0f ? 1.0f : x;  // NaN passes through
  const float a = std::abs(x);
  const float p =
      1.5707963050f +
      a * (-0.2145988016f +
           a * (0.0889789874f +
                a * (-0.0501743046f +
                     a * (0.0308918810f +
                          a * (-0.0170881256f + a * (0.0066700901f + a * -0.0012624911f))))));
  const float r = std::sqrt(1.0f - a) * p;
  return x < 0.0f ? kPi - r : r;
}

inline float fastAtan2(float y, float x) {
  const float ax = std::abs(x), ay = std::abs(y);
  const float hi = ax > ay ? ax : ay, lo = ax > ay ? ay : ax;
  if (!(hi > 0.0f) || !(hi <= 3.4e38f)) return std::atan2(y, x);  // zeros, infinities, NaN
  const float z = lo / hi, z2 = z * z;
  float a =
      z *
      (1.0f + z2 * (-0.3333314528f +
                    z2 * (0.1999355085f +
                          z2 * (-0.1420889944f +
                                z2 * (0.1065626393f +
                                      z2 * (-0.0752896400f +
                                            z2 * (0.0429096138f +
                                                  z2 * (-0.0161657367f + z2 * 0.0028662257f))))))));
  if (ay > ax) a = 0.5f * kPi - a;
  if (std::signbit(x)) a = kPi - a;
  return std::copysign(a, y);
}

}  // namespace meso
