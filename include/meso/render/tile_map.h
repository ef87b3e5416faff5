// DESIGN.md section 4, "the surface's own metric" (docs/metric.md): an affine map of (u, v, height)
// space keeps orthographic projection and occlusion, so the relief on a surface with any P_u, P_v
// is the image of a unit-metric tile under M = [P_u / l, P_v / l, N]. Visible normals seen from V
// are the tile's seen from M^-1 V, mapped back by the inverse transpose M^-T.
#pragma once

#include "meso/core/math.h"

#include <algorithm>
#include <cmath>

namespace meso {

struct TileMap {
  Vec3 a{1, 0, 0}, b{0, 1, 0},
      N{0, 0, 1};  // the columns of M: P_u / l, P_v / l (in the tangent plane), N
  Vec3 aDual{1, 0, 0},
      bDual{0, 1, 0};  // aDual.a = bDual.b = 1, aDual.b = bDual.a = 0, both tangent

  // M^-1 w: a world direction in tile coordinates.
  Vec3 toTile(const Vec3& w) const {
    return {glm::dot(aDual, w), glm::dot(bDual, w), glm::dot(N, w)};
  }
  // M^T n: a world normal as a tile normal (not normalized).
  Vec3 normalToTile(const Vec3& n) const {
    return {glm::dot(a, n), glm::dot(b, n), glm::dot(N, n)};
  }
  // M^-T n: a tile normal as a world normal (not normalized).
  Vec3 normalToWorld(const Vec3& n) const { return n.x * aDual + n.y * bDual + n.z * N; }
};

// The map of a frame for a tile whose unit of u is lengthPerU long. P_u and P_v are projected onto
// the plane normal to N (a shading frame's N need not be normal to its tangents). A degenerate
// frame (parallel or vanishing tangents, non-finite values) gets an orthonormal map around N.
inline TileMap makeTileMap(const Vec3& Pu, const Vec3& Pv, const Vec3& N, float lengthPerU) {
  TileMap m;
  m.N = N;
  const float inv = 1.0f / lengthPerU;
  const Vec3 a = (Pu - glm::dot(Pu, N) * N) * inv, b = (Pv - glm::dot(Pv, N) * N) * inv;
  const float aa = glm::dot(a, a), ab = glm::dot(a, b), bb = glm::dot(b, b);
  const float det = aa * bb - ab * ab;
  if (!(det > 1e-12f * aa * bb) || !std::isfinite(det)) {
    const Vec3 h = std::abs(N.x) < 0.9f ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    m.a = m.aDual = glm::normalize(h - glm::dot(h, N) * N);
    m.b = m.bDual = glm::cross(N, m.a);
    return m;
  }
  m.a = a;
  m.b = b;
  // [aDual, bDual] = [a, b] G^-1 with the Gram matrix G = [[aa, ab], [ab, bb]].
  m.aDual = (bb * a - ab * b) / det;
  m.bDual = (aa * b - ab * a) / det;
  return m;
}

// The length per unit of u a tile map uses for a frame of length `own` with tables built at the
// class lengths l0 and l1 around the surface's metric: `own` between them, where the tables are
// mixed in log l; the nearer of the two outside (a frame stretched beyond the classes, as a finer
// level's on displaced coarser levels), so that the map carries the rest of the stretch to the
// tables' relief. A non-finite or non-positive result falls back to `own`.
inline float tableLengthPerU(float own, float l0, float l1) {
  const float length = std::clamp(own, std::min(l0, l1), std::max(l0, l1));
  return std::isfinite(length) && length > 0.0f ? length : own;
}

// sqrt(|P_u x P_v|): the isotropic length per unit of u that keeps areas (the metric class axis).
inline float areaLengthPerU(const Vec3& Pu, const Vec3& Pv) {
  return std::sqrt(glm::length(glm::cross(Pu, Pv)));
}

}  // namespace meso
