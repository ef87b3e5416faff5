// Camera paths for fly-throughs: keyframes interpolated by cubic Hermite splines with Catmull-Rom
// tangents for non-uniform times, so the path passes through every keyframe with a continuous
// first derivative (no kinks).
#pragma once

#include "meso/scene/scene.h"

#include <vector>

namespace meso {

class CameraPath {
 public:
  // Throws meso::Error unless there is at least one keyframe and times strictly increase.
  explicit CameraPath(std::vector<CameraKeyframe> keys);

  float startTime() const { return keys_.front().time; }
  float endTime() const { return keys_.back().time; }
  // The interpolated keyframe at time t (clamped to the path's span).
  CameraKeyframe at(float t) const;
  // Camera settings for frame i of n frames spread evenly over the path (both ends included),
  // with resolution and spp from `base`.
  CameraSettings frame(int i, int n, const CameraSettings& base) const;

 private:
  std::vector<CameraKeyframe> keys_;
};

}  // namespace meso
