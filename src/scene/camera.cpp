#include "meso/scene/camera.h"

#include <cmath>

namespace meso {

Camera::Camera(const CameraSettings& settings) : settings_(settings) {
  forward_ = glm::normalize(settings.lookAt - settings.position);
  right_ = glm::normalize(glm::cross(forward_, settings.up));
  up_ = glm::cross(right_, forward_);
  tanHalfFovY_ = std::tan(radians(settings.fovY) * 0.5f);
  // Near the centre one pixel subtends (2 tan(fov/2) / height) radians.
  pixelsPerRadian_ = static_cast<float>(settings.height) / (2.0f * tanHalfFovY_);
}

Ray Camera::generateRay(float x, float y) const {
  const float aspect = static_cast<float>(settings_.width) / static_cast<float>(settings_.height);
  const float sx = (2.0f * x / static_cast<float>(settings_.width) - 1.0f) * tanHalfFovY_ * aspect;
  const float sy = (1.0f - 2.0f * y / static_cast<float>(settings_.height)) * tanHalfFovY_;
  Ray ray;
  ray.origin = settings_.position;
  ray.direction = glm::normalize(forward_ + sx * right_ + sy * up_);
  return ray;
}

}  // namespace meso
