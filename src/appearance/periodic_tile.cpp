// The infinite periodic relief: one tile in Embree, rays re-entering from the opposite side.
#include "meso/appearance/periodic_tile.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace meso {

PeriodicTile::PeriodicTile(const PeriodicRelief& relief, int n) {
  TessellatedMesh mesh;
  zMin_ = std::numeric_limits<float>::max();
  zMax_ = -zMin_;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const float x = static_cast<float>(i) / n, y = static_cast<float>(j) / n;
      const float z = relief.height(x, y);
      mesh.positions.emplace_back(x, y, z);
      zMin_ = std::min(zMin_, z);
      zMax_ = std::max(zMax_, z);
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
    float tExit = std::numeric_limits<float>::infinity();
    int axis = -1;
    for (int a = 0; a < 2; ++a) {
      if (d[a] == 0.0f) continue;
      const float t = ((d[a] > 0.0f ? 1.0f : 0.0f) - o[a]) / d[a];
      if (t < tExit) tExit = t, axis = a;
    }
    if (axis < 0) return d.z <= 0.0f || o.z <= zMax_ ? scene_.occluded(Ray{o, d}) : false;
    if (scene_.occluded(Ray{o, d, 0.0f, std::max(tExit, 0.0f) * 1.0001f + 1e-6f})) return true;
    o += tExit * d;
    o[axis] = d[axis] > 0.0f ? 0.0f : 1.0f;
    if (d.z <= 0.0f && o.z < zMin_ - 1e-3f)
      return false;  // left through the bottom: the relief is a height field above it
  }
  return true;
}

bool PeriodicTile::traceHit(Vec3 o, const Vec3& d, Vec3& hitP) const {
  for (int crossing = 0; crossing < 100000; ++crossing) {
    float tExit = std::numeric_limits<float>::infinity();
    int axis = -1;
    for (int a = 0; a < 2; ++a) {
      if (d[a] == 0.0f) continue;
      const float t = ((d[a] > 0.0f ? 1.0f : 0.0f) - o[a]) / d[a];
      if (t < tExit) tExit = t, axis = a;
    }
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
