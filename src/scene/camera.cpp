#include "meso/scene/camera.h"

namespace meso {

Camera::Camera(const CameraSettings& settings)
    : settings_(settings),
      screen_(ScreenMetric::lookAt(settings.position, settings.lookAt, settings.up, settings.fovY,
                                   settings.width, settings.height)) {
  // Near the centre one pixel subtends (2 tan(fov/2) / height) radians.
  pixelsPerRadian_ = static_cast<float>(settings.height) / (2.0f * screen_.tanHalfFovY);
}

Ray Camera::generateRay(float x, float y) const {
  const float tanHalfFovY = screen_.tanHalfFovY;
  const float aspect = static_cast<float>(settings_.width) / static_cast<float>(settings_.height);
  const float sx = (2.0f * x / static_cast<float>(settings_.width) - 1.0f) * tanHalfFovY * aspect;
  const float sy = (1.0f - 2.0f * y / static_cast<float>(settings_.height)) * tanHalfFovY;
  Ray ray;
  ray.origin = settings_.position;
  ray.direction = glm::normalize(screen_.forward + sx * screen_.right + sy * screen_.up);
  return ray;
}

}  // namespace meso
