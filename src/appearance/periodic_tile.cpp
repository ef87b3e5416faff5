// The infinite periodic relief: one tile in Embree, rays re-entering from the opposite side.
#include "meso/appearance/periodic_tile.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>

namespace meso {
namespace {

// x - floor(x), without a libm call (floor is one on baseline x86-64, and horizon() is hot).
double wrapToTile(double x) {
  const double f = x - static_cast<double>(static_cast<int64_t>(x));
  return f < 0.0 ? f + 1.0 : f;
}

// The horizontal distance along u from o to its (maxTiles - 1)-th crossing of a tile side: the
// last place where occluded() looks whether its ray has risen above the relief.
double capDistance(const Vec3& o, Vec2 u, int maxTiles) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double x = o.x - std::floor(o.x), y = o.y - std::floor(o.y), r = 0.0;
  for (int crossing = 0; crossing + 1 < maxTiles; ++crossing) {
    const double tx = u.x > 0.0f ? (1.0 - x) / u.x : u.x < 0.0f ? -x / u.x : kInf;
    const double ty = u.y > 0.0f ? (1.0 - y) / u.y : u.y < 0.0f ? -y / u.y : kInf;
    if (tx <= ty) {
      r += tx, y += tx * u.y, x = u.x > 0.0f ? 0.0 : 1.0;
    } else {
      r += ty, x += ty * u.x, y = u.y > 0.0f ? 0.0 : 1.0;
    }
  }
  return r;
}

// Where the ray o + t d leaves the tile's x, y range [0, 1]^2: t, and the axis it leaves through
// (-1 for a vertical ray, t infinite).
float tileExit(const Vec3& o, const Vec3& d, int& axis) {
  float tExit = std::numeric_limits<float>::infinity();
  axis = -1;
  for (int a = 0; a < 2; ++a) {
    if (d[a] == 0.0f) continue;
    const float t = ((d[a] > 0.0f ? 1.0f : 0.0f) - o[a]) / d[a];
    if (t < tExit) tExit = t, axis = a;
  }
  return tExit;
}

}  // namespace

PeriodicTile::PeriodicTile(const PeriodicRelief& relief, int n) : n_(n) {
  TessellatedMesh mesh;
  zMin_ = std::numeric_limits<float>::max();
  zMax_ = -zMin_;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const float x = static_cast<float>(i) / n, y = static_cast<float>(j) / n;
      const float z = relief.height(x, y);
      mesh.positions.emplace_back(x, y, z);
      heights_.push_back(z);
      zMin_ = std::min(zMin_, z);
      zMax_ = std::max(zMax_, z);
    }
  std::vector<float> quads(static_cast<size_t>(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float* h = &heights_[static_cast<size_t>(j) * (n + 1) + i];
      quads[static_cast<size_t>(j) * n + i] = std::max({h[0], h[1], h[n + 1], h[n + 2]});
    }
  maxLevels_.push_back(std::move(quads));
  for (int side = n; side > 1;) {
    const std::vector<float>& fine = maxLevels_.back();
    const int coarse = (side + 1) / 2;
    std::vector<float> level(static_cast<size_t>(coarse) * coarse, zMin_);
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i) {
        float& m = level[static_cast<size_t>(j / 2) * coarse + i / 2];
        m = std::max(m, fine[static_cast<size_t>(j) * side + i]);
      }
    maxLevels_.push_back(std::move(level));
    side = coarse;
  }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      for (uint32_t v : {a, b, d, a, d, c}) mesh.indices.push_back(v);
      mesh.triangleFace.insert(mesh.triangleFace.end(), 2, 0);
      mesh.cornerSt.insert(mesh.cornerSt.end(), 6, Vec2(0.0f));
    }
  scene_.addMesh(mesh);
  scene_.commit();
}

bool PeriodicTile::trace(Vec3 o, const Vec3& d, Vec2& hitXY) const {
  Vec3 hit;
  if (!traceHit(o, d, hit)) return false;
  hitXY = {hit.x, hit.y};
  return true;
}

bool PeriodicTile::occluded(Vec3 o, const Vec3& d, int maxTiles) const {
  o.x -= std::floor(o.x);
  o.y -= std::floor(o.y);
  for (int crossing = 0; crossing < maxTiles; ++crossing) {
    if (d.z > 0.0f && o.z > zMax_) return false;
    int axis = -1;
    const float tExit = tileExit(o, d, axis);
    if (axis < 0) return d.z <= 0.0f || o.z <= zMax_ ? scene_.occluded(Ray{o, d}) : false;
    if (scene_.occluded(Ray{o, d, 0.0f, std::max(tExit, 0.0f) * 1.0001f + 1e-6f})) return true;
    o += tExit * d;
    o[axis] = d[axis] > 0.0f ? 0.0f : 1.0f;
    if (d.z <= 0.0f && o.z < zMin_ - 1e-3f)
      return false;  // left through the bottom: the relief is a height field above it
  }
  return true;
}

// The triangle of quad (i, j) under local coordinates (fx, fy): the quad is split along its
// diagonal from (i, j) to (i + 1, j + 1), as the constructor triangulates it.
float PeriodicTile::cellHeight(int i, int j, double fx, double fy) const {
  const float* r0 = &heights_[static_cast<size_t>(j) * (n_ + 1) + i];
  const double ha = r0[0], hb = r0[1], hc = r0[n_ + 1], hd = r0[n_ + 2];
  return static_cast<float>(fx >= fy ? ha + fx * (hb - ha) + fy * (hd - hb)
                                     : ha + fy * (hc - ha) + fx * (hd - hc));
}

float PeriodicTile::horizon(const Vec3& origin, Vec2 u, std::span<const float> slopes,
                            int maxTiles) const {
  // slopes[0, k) are at or below the horizon found so far; a light at or below the tile's plane is
  // blocked (occluded() never sees such a ray rise above the relief).
  size_t k = 0;
  double found = 0.0;
  const auto raise = [&](double s) {
    if (!(s > found)) return;
    found = s;
    while (k < slopes.size() && slopes[k] <= found) ++k;
  };
  while (k < slopes.size() && slopes[k] <= found) ++k;
  // Distances r in quads; a point at height z and distance r is at slope n (z - z0) / r.
  const double n = n_, z0 = origin.z, top = n * (static_cast<double>(zMax_) - z0);
  // occluded() gives up at its (maxTiles - 1)-th tile side. Within r (in tiles) the line crosses
  // fewer than 2 + r (|u.x| + |u.y|) sides, so that side is no nearer than this bound, which
  // stands for it until the march gets there.
  const double ux = u.x, uy = u.y;
  double rCap = std::max(maxTiles - 3, 0) / (std::abs(ux) + std::abs(uy)) * n;
  bool exactCap = false;
  if (!(rCap > 0.0)) {
    rCap = capDistance(origin, u, maxTiles) * n, exactCap = true;
    if (!(rCap > 0.0)) return z0 > zMax_ ? 0.0f : std::numeric_limits<float>::infinity();
  }
  const double invUx = ux != 0.0 ? 1.0 / ux : 0.0, invUy = uy != 0.0 ? 1.0 / uy : 0.0;
  double X = wrapToTile(origin.x) * n, Y = wrapToTile(origin.y) * n;
  int i = std::clamp(static_cast<int>(X), 0, n_ - 1),
      j = std::clamp(static_cast<int>(Y), 0, n_ - 1);
  double r = 0.0;
  // Moves to where the line leaves the box [x0, x1] x [y0, y1] (in quads), into the next quad.
  const auto leave = [&](int x0, int x1, int y0, int y1) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const double tx = ux > 0.0 ? (x1 - X) * invUx : ux < 0.0 ? (x0 - X) * invUx : kInf;
    const double ty = uy > 0.0 ? (y1 - Y) * invUy : uy < 0.0 ? (y0 - Y) * invUy : kInf;
    const double t = std::max(std::min(tx, ty), 0.0);
    if (tx <= ty) {
      X = ux > 0.0 ? x1 : x0, Y += t * uy;
      i = ux > 0.0 ? x1 : x0 - 1, j = Y < 0.0 ? -1 : static_cast<int>(Y);
    } else {
      Y = uy > 0.0 ? y1 : y0, X += t * ux;
      j = uy > 0.0 ? y1 : y0 - 1, i = X < 0.0 ? -1 : static_cast<int>(X);
    }
    if (i >= n_) i -= n_, X -= n;  // into the next periodic copy
    if (i < 0) i += n_, X += n;
    if (j >= n_) j -= n_, Y -= n;
    if (j < 0) j += n_, Y += n;
    r += t;
    return t;
  };
  const int levels = static_cast<int>(maxLevels_.size());
  int level = 0;
  const auto below = [&](int l) {
    const int side = (n_ + (1 << l) - 1) >> l;
    const float m = maxLevels_[l][static_cast<size_t>(j >> l) * side + (i >> l)];
    return n * (m - z0) < slopes[k] * r;
  };
  while (k < slopes.size() && !(top < slopes[k] * r)) {
    if (r >= rCap) {
      if (exactCap) break;
      rCap = capDistance(origin, u, maxTiles) * n, exactCap = true;
      continue;
    }
    // The coarsest block around (i, j) below the lowest slope still above the horizon is skipped.
    if (below(level)) {
      while (level + 1 < levels && below(level + 1)) ++level;
      const int x0 = (i >> level) << level, y0 = (j >> level) << level;
      leave(x0, std::min(x0 + (1 << level), n_), y0, std::min(y0 + (1 << level), n_));
      continue;
    }
    if (level > 0) {
      --level;
      continue;
    }
    const int ci = i, cj = j;
    const double fx0 = X - ci, fy0 = Y - cj, r0 = r;
    const double t = leave(ci, ci + 1, cj, cj + 1);
    if (!(t > 0.0)) continue;
    // The height along the line is linear on each triangle, so the slope peaks where the line
    // crosses the quad's diagonal or leaves the quad.
    const double fx1 = fx0 + t * ux, fy1 = fy0 + t * uy;
    const double g0 = fx0 - fy0, g1 = fx1 - fy1;
    if ((g0 < 0.0) != (g1 < 0.0) && g0 != g1) {
      const double a = g0 / (g0 - g1);
      if (r0 + a * t > 0.0)
        raise(n * (cellHeight(ci, cj, fx0 + a * t * ux, fy0 + a * t * uy) - z0) / (r0 + a * t));
    }
    raise(n * (cellHeight(ci, cj, fx1, fy1) - z0) / (r0 + t));
  }
  // Still below the relief's top where occluded() stops: blocked. (Stopped before: the lights
  // left are above top / r > top / rCap.)
  if (exactCap && r >= rCap) raise(top / rCap);
  // The largest float not above the horizon: a float slope is above it exactly when above this.
  const float result = static_cast<float>(found);
  return result > found ? std::bit_cast<float>(std::bit_cast<uint32_t>(result) - 1u) : result;
}

bool PeriodicTile::traceHit(Vec3 o, const Vec3& d, Vec3& hitP) const {
  for (int crossing = 0; crossing < 100000; ++crossing) {
    int axis = -1;
    const float tExit = tileExit(o, d, axis);
    // Slightly past the exit so that hits exactly on the tile's side are not lost.
    Ray ray{o, d, 0.0f, std::max(tExit, 0.0f) * 1.0001f + 1e-6f};
    RayHit hit;
    if (scene_.intersect(ray, hit)) {
      const Vec3 p = o + hit.t * d;
      hitP = {p.x - std::floor(p.x), p.y - std::floor(p.y), p.z};
      return true;
    }
    if (axis < 0 || o.z + tExit * d.z < zMin_ - 1e-3f) return false;
    o += tExit * d;
    o[axis] = d[axis] > 0.0f ? 0.0f : 1.0f;  // re-enter the tile from the opposite side
  }
  return false;
}

}  // namespace meso
