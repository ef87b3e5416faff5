// Becker & Max 1993, section 2.1: the paper rendered a patch with a z-buffer and copied it to its
// neighbours back to front; here rays wrap around the periodic tile (PeriodicTile), so any number
// of neighbours occlude, which matters near grazing (at 89 degrees a ray crosses tens of tiles).
#include "meso/appearance/histogram_builder.h"

#include "meso/core/rng.h"
#include "meso/appearance/class_map.h"
#include "meso/appearance/periodic_tile.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace meso {
namespace {

// The rays of view slice (k, j): the traced azimuths a with a * phiV / azimuths = j, in order (each
// slice is written by one task, so its sums do not depend on the thread count).
void traceSlice(const PeriodicRelief& relief, const PeriodicTile& tile, const HistogramSettings& s,
                int k, int j, VisibleNormalHistogram& h) {
  const float thetaV = h.thetaV(k);
  const int phiV = h.resolution().phiV;
  const int slice = h.sliceOf(k, j);
  const int first = (j * s.azimuths + phiV - 1) / phiV,
            end = ((j + 1) * s.azimuths + phiV - 1) / phiV;
  for (int a = first; a < end; ++a) {
    Rng rng(s.seed, static_cast<uint64_t>(k) * s.azimuths + a);
    const float phiV = 2.0f * kPi * (static_cast<float>(a) + 0.5f) / static_cast<float>(s.azimuths);
    const Vec3 towardEye(std::sin(thetaV) * std::cos(phiV), std::sin(thetaV) * std::sin(phiV),
                         std::cos(thetaV));
    // Rays go into the tile by M^-1, normals come back by M^-T (class_map.h).
    const ClassMap map{s.shape};
    const Vec3 tileEye = map.toTile(towardEye);
    const float c = std::cos(-phiV), sn = std::sin(-phiV);
    for (int r = 0; r < s.raysPerView; ++r) {
      // Uniform origins on a plane above the relief are uniform in projected area.
      const Vec3 o(rng.uniform(), rng.uniform(), tile.zMax() + 1e-3f);
      Vec2 xy;
      if (!tile.trace(o, -tileEye, xy)) continue;
      const Vec2 g = relief.gradient(xy.x, xy.y);
      const Vec3 n = map.normalFromTile(Vec3(-g.x, -g.y, 1.0f));
      // Into the view-aligned frame: rotate by -phi_V about z.
      h.add(slice, Vec3(c * n.x - sn * n.y, sn * n.x + c * n.y, n.z));
    }
  }
}

}  // namespace

VisibleNormalHistogram buildVisibleNormalHistogram(const PeriodicRelief& relief,
                                                   const HistogramSettings& s) {
  const PeriodicTile tile(relief, std::max(s.meshResolution, 1));
  VisibleNormalHistogram h(s.resolution);
  // One task per view slice: grazing slices cost several times the others, so slices of one
  // theta_V row would leave a core idle at the end.
  const int phiV = h.resolution().phiV;
  tbb::parallel_for(0, h.resolution().thetaV * phiV,
                    [&](int t) { traceSlice(relief, tile, s, t / phiV, t % phiV, h); });
  h.normalize();
  return h;
}

}  // namespace meso
