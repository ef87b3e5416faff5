// Private to src/geometry: how the micropolygon cap (DicingSettings::maxMicropolygons) coarsens
// the dicing, farthest geometry first, so that the near field stays diced as asked.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace meso {

// The rate (segments) for x asked-for segments: ceil(x) clamped to [1, limit]; NaN gives 1. Mesh
// edges and split faces' sub-quads both round this way.
inline int toRate(float x, int limit) {
  if (!(x > 1.0f)) return 1;
  return static_cast<int>(std::min(std::ceil(x), static_cast<float>(limit)));
}

// Each unit diced at one rate (a mesh edge, the sub-quad of a split face) is coarsened by
// factor(d), d the distance from the eye to its nearest point: 1 nearer than `beyond` (D), d / D
// beyond it. With the isotropic metric every octave of distance on a ground costs about the same
// triangles, and d / D makes each octave beyond D cost a quarter of the one before (rates fall as
// 1 / d more, triangles as their square): the far field costs 4/3 of one octave, so D lies about
// 4/3 octave nearer than where dropping everything beyond it to rate 1 would put it, while the
// micropolygons grow only in proportion to d / D. A function of the unit's own distance, so a
// mesh edge gets one rate for both its faces (no cracks). Below `floor` distances count as `floor`:
// when even D = floor is over the cap, every unit is coarsened by at least floor / D.
struct CapCoarsening {
  float beyond = std::numeric_limits<float>::infinity();
  float floor = 0.0f;
  // NaN distances are not coarsened.
  float factor(float distance) const {
    const float f = std::max(distance, floor) / beyond;
    return f > 1.0f ? f : 1.0f;
  }
};

}  // namespace meso
