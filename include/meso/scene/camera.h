// The pinhole camera: rays through film positions, and the pixel scale the transition needs. Its
// frame is the ScreenMetric that dicing measures pixels with (geometry/adaptive_tessellation.h):
// one pinhole model for rays and micropolygons.
#pragma once

#include "meso/geometry/adaptive_tessellation.h"
#include "meso/geometry/ray_scene.h"
#include "meso/scene/scene.h"

namespace meso {

class Camera {
 public:
  explicit Camera(const CameraSettings& settings);

  // The primary ray through film position (x, y) in pixels, (0, 0) the top-left corner of the
  // image and (width, height) the bottom-right one; direction normalized.
  Ray generateRay(float x, float y) const;

  // Pixels per radian at the image centre: p of DESIGN.md section 3.
  float pixelsPerRadian() const { return pixelsPerRadian_; }
  Vec3 position() const { return settings_.position; }
  const CameraSettings& settings() const { return settings_; }
  // The camera frame and field of view, as dicing sees them.
  const ScreenMetric& screen() const { return screen_; }

 private:
  CameraSettings settings_;
  ScreenMetric screen_;  // eye, orthonormal forward/right/up, tan(fov / 2), size in pixels
  float pixelsPerRadian_;
};

}  // namespace meso
