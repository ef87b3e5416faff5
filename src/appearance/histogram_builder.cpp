// Becker & Max 1993, section 2.1: the paper rendered a patch with a z-buffer and copied it to its
// neighbours back to front; here rays wrap around the periodic tile, so any number of neighbours
// occlude, which matters near grazing (at 89 degrees a ray crosses tens of tiles).
#include "meso/appearance/histogram_builder.h"

#include "meso/core/rng.h"
#include "meso/geometry/ray_scene.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace meso {
namespace {

struct Tile {
  RayScene scene;
  float zMin = 0.0f;
  float zMax = 0.0f;
};

// The height field over [0,1]^2 as triangles; edge vertices sit exactly on x, y = 0 and 1.
void buildTile(const PeriodicRelief& relief, int n, Tile& tile) {
  TessellatedMesh mesh;
  tile.zMin = std::numeric_limits<float>::max();
  tile.zMax = -tile.zMin;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const float x = static_cast<float>(i) / n, y = static_cast<float>(j) / n;
      const float z = relief.height(x, y);
      mesh.positions.emplace_back(x, y, z);
      tile.zMin = std::min(tile.zMin, z);
      tile.zMax = std::max(tile.zMax, z);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      for (uint32_t v : {a, b, d, a, d, c}) mesh.indices.push_back(v);
      mesh.triangleFace.insert(mesh.triangleFace.end(), 2, 0);
      mesh.cornerSt.insert(mesh.cornerSt.end(), 6, Vec2(0.0f));
    }
  tile.scene.addMesh(mesh);
  tile.scene.commit();
}

// Follows a ray through the periodic tiles until it hits; returns the hit's tile coordinates.
bool tracePeriodic(const Tile& tile, Vec3 o, const Vec3& d, Vec2& hitXY) {
  for (int crossing = 0; crossing < 100000; ++crossing) {
    float tExit = std::numeric_limits<float>::infinity();
    int axis = -1;
    for (int a = 0; a < 2; ++a) {
      if (d[a] == 0.0f) continue;
      const float t = ((d[a] > 0.0f ? 1.0f : 0.0f) - o[a]) / d[a];
      if (t < tExit) tExit = t, axis = a;
    }
    Ray ray{o, d, 0.0f, std::max(tExit, 0.0f) * 1.0001f + 1e-6f};
    RayHit hit;
    if (tile.scene.intersect(ray, hit)) {
      const Vec3 p = o + hit.t * d;
      hitXY = {p.x - std::floor(p.x), p.y - std::floor(p.y)};
      return true;
    }
    if (axis < 0 || o.z + tExit * d.z < tile.zMin - 1e-3f) return false;
    o += tExit * d;
    o[axis] = d[axis] > 0.0f ? 0.0f : 1.0f;  // re-enter the tile from the opposite side
  }
  return false;
}

void traceSlice(const PeriodicRelief& relief, const Tile& tile, const HistogramSettings& s, int k,
                VisibleNormalHistogram& h) {
  const float thetaV = h.thetaV(k);
  for (int a = 0; a < s.azimuths; ++a) {
    Rng rng(s.seed, static_cast<uint64_t>(k) * s.azimuths + a);
    const float phiV = 2.0f * kPi * (static_cast<float>(a) + 0.5f) / static_cast<float>(s.azimuths);
    const Vec3 towardEye(std::sin(thetaV) * std::cos(phiV), std::sin(thetaV) * std::sin(phiV), std::cos(thetaV));
    const float c = std::cos(-phiV), sn = std::sin(-phiV);
    for (int r = 0; r < s.raysPerView; ++r) {
      // Uniform origins on a plane above the relief are uniform in projected area.
      const Vec3 o(rng.uniform(), rng.uniform(), tile.zMax + 1e-3f);
      Vec2 xy;
      if (!tracePeriodic(tile, o, -towardEye, xy)) continue;
      const Vec2 g = relief.gradient(xy.x, xy.y);
      const Vec3 n = glm::normalize(Vec3(-g.x, -g.y, 1.0f));
      // Into the view-aligned frame: rotate by -phi_V about z.
      h.add(k, Vec3(c * n.x - sn * n.y, sn * n.x + c * n.y, n.z));
    }
  }
}

}  // namespace

VisibleNormalHistogram buildVisibleNormalHistogram(const PeriodicRelief& relief, const HistogramSettings& s) {
  Tile tile;
  buildTile(relief, std::max(s.meshResolution, 1), tile);
  VisibleNormalHistogram h(s.resolution);
  tbb::parallel_for(0, h.resolution().thetaV, [&](int k) { traceSlice(relief, tile, s, k, h); });
  h.normalize();
  return h;
}

}  // namespace meso
