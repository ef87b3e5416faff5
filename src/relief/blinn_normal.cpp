// Becker & Max 1993, eq. 4 (Blinn 1978): N' = N + B_u (n x P_v) - B_v (n x P_u), normalized.
#include "meso/relief/blinn_normal.h"

#include <algorithm>
#include <cmath>

namespace meso {
namespace {

// N normalized, or `fallback` when N is zero or not finite. A vector already of unit length (to
// 5e-7, a few float roundings: the frames' normals) is returned as it is. One squared length
// serves both tests: a component that is not finite, or whose square overflows, makes it (and its
// root) infinite or NaN.
inline Vec3 unitOr(const Vec3& v, const Vec3& fallback) {
  const float squared = glm::dot(v, v);
  if (std::abs(squared - 1.0f) < 1e-6f) return v;
  const float len = std::sqrt(squared);
  return len > 1e-30f && std::isfinite(len) ? v / len : fallback;
}

}  // namespace

// Derivation: P' = P + h n with |n| = 1 has P'_u = P_u + B_u n + h n_u. Dropping h n_u (Blinn's
// "insignificant terms": n_u is tangent, so h n_u changes P'_u x P'_v only along n, i.e. its
// length, and moves the direction by O(h^2)), P'_u x P'_v = P_u x P_v + B_u (n x P_v) + B_v (P_u x
// n), since n x n = 0. The cross terms need the unit n; eq. 4 writes the unnormalized N = P_u x
// P_v.
Vec3 blinnNormal(const Vec3& Pu, const Vec3& Pv, const Vec3& N, float Bu, float Bv) {
  const Vec3 n = unitOr(N, Vec3(0.0f, 0.0f, 1.0f));
  const Vec3 area = glm::cross(Pu, Pv);
  const float areaLength = glm::length(area);
  if (!(areaLength > 1e-30f) || !std::isfinite(areaLength) || !std::isfinite(Bu) ||
      !std::isfinite(Bv))
    return n;
  // Scale everything by 1 / max(1, |B|) so that huge slopes neither overflow nor lose the frame.
  const float s = 1.0f / std::max({1.0f, std::abs(Bu), std::abs(Bv)});
  Vec3 r = s * area + (s * Bu) * glm::cross(n, Pv) - (s * Bv) * glm::cross(n, Pu);
  if (glm::dot(area, n) < 0.0f) r = -r;  // P_u x P_v points away from N: keep facing like N
  return unitOr(r, n);
}

Vec3 blinnNormal(const Vec3& Pu, const Vec3& Pv, float Bu, float Bv) {
  return blinnNormal(Pu, Pv, glm::cross(Pu, Pv), Bu, Bv);
}

}  // namespace meso
