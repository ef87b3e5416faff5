// The statistics of a relief level (relief_level.h).
#include "meso/relief/relief_level.h"

#include "meso/core/rng.h"

#include <algorithm>
#include <cmath>

namespace meso {

std::vector<Vec2> levelSamplePoints(const ReliefLevel& level) {
  const bool table = level.source && level.source->texelsPerSide() > 0;
  const float span = table && level.scale > 0.0f ? 1.0f / level.scale : 64.0f * level.wavelength();
  Rng rng(0x51073);
  std::vector<Vec2> points(1024);
  for (Vec2& p : points) p = Vec2(rng.uniform(), rng.uniform()) * span;
  return points;
}

int tableMeshResolution(const ReliefLevel& level, int base) {
  const int texels = level.source ? level.source->texelsPerSide() : 0;
  if (texels <= 0) return base;
  const float perCycle = 8.0f * level.source->highestFrequency();
  const int resolve = static_cast<int>(std::min(
      2.0f * static_cast<float>(texels), std::isfinite(perCycle) ? std::ceil(perCycle) : 0.0f));
  return std::clamp(resolve, base, std::max(base, kMaxTableMeshResolution));
}

double levelSlopeMeanSquarePerU(const ReliefLevel& level) {
  const std::vector<Vec2> points = levelSamplePoints(level);
  double uu = 0.0, vv = 0.0;
  for (const Vec2& uv : points) {
    const Vec2 B = level.derivatives(uv);
    uu += static_cast<double>(B.x) * B.x;
    vv += static_cast<double>(B.y) * B.y;
  }
  return std::max(uu, vv) / static_cast<double>(points.size());
}

}  // namespace meso
