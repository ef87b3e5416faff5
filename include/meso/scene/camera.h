// The pinhole camera: rays through film positions, and the pixel scale the transition needs.
#pragma once

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

 private:
  CameraSettings settings_;
  Vec3 forward_, right_, up_;  // orthonormal camera frame
  float tanHalfFovY_;
  float pixelsPerRadian_;
};

}  // namespace meso
