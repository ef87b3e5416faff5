// A pinhole view as dicing sees it (screen_metric.h).
#include "meso/geometry/screen_metric.h"

#include <algorithm>
#include <cmath>

namespace meso {

ScreenMetric ScreenMetric::lookAt(Vec3 eye, Vec3 target, Vec3 up, float fovYDegrees, int width,
                                  int height) {
  ScreenMetric m;
  m.eye = eye;
  m.forward = glm::normalize(target - eye);
  m.right = glm::normalize(glm::cross(m.forward, up));
  m.up = glm::cross(m.right, m.forward);
  m.tanHalfFovY = std::tan(radians(fovYDegrees) * 0.5f);
  m.width = width;
  m.height = height;
  return m;
}

float ScreenMetric::pixelsPerUnit(float z) const {
  return static_cast<float>(height) / (2.0f * tanHalfFovY * std::max(z, nearDistance));
}

Vec2 ScreenMetric::toPixels(Vec3 p) const {
  const Vec3 d = p - eye;
  const float scale = pixelsPerUnit(glm::dot(d, forward));
  return Vec2(0.5f * static_cast<float>(width) + glm::dot(d, right) * scale,
              0.5f * static_cast<float>(height) - glm::dot(d, up) * scale);
}

float ScreenMetric::projectedLength(Vec3 a, Vec3 b) const {
  const float za = depth(a), zb = depth(b);
  if (!(za >= nearDistance) && !(zb >= nearDistance)) return 0.0f;
  // Clip to the near plane: the part behind it is not seen, and its projection would blow up.
  if (za < nearDistance) a += (b - a) * ((nearDistance - za) / (zb - za));
  if (zb < nearDistance) b += (a - b) * ((nearDistance - zb) / (za - zb));
  return glm::length(toPixels(a) - toPixels(b));
}

float ScreenMetric::pixelDensity(Vec3 p) const {
  const float z = std::max(depth(p), nearDistance);
  // Off screen the stretch is that of the image corner: an edge that leaves the view far to the
  // side is not diced more finely than where it is seen.
  const float tx = tanHalfFovY * static_cast<float>(width) / static_cast<float>(height);
  const float corner = std::sqrt(1.0f + tx * tx + tanHalfFovY * tanHalfFovY);
  return pixelsPerUnit(z) * std::clamp(glm::length(p - eye) / z, 1.0f, corner);
}

float ScreenMetric::footprintLength(Vec3 a, Vec3 b) const {
  const float za = depth(a), zb = depth(b);
  if (!(za >= nearDistance) && !(zb >= nearDistance)) return 0.0f;
  if (za < nearDistance) a += (b - a) * ((nearDistance - za) / (zb - za));
  if (zb < nearDistance) b += (a - b) * ((nearDistance - zb) / (za - zb));
  const float mean =
      (pixelDensity(a) + 4.0f * pixelDensity(0.5f * (a + b)) + pixelDensity(b)) / 6.0f;
  return std::max(glm::length(b - a) * mean, projectedLength(a, b));
}

bool ScreenMetric::pointInView(Vec3 p) const {
  if (!(depth(p) >= nearDistance)) return false;
  const Vec2 q = toPixels(p);
  return q.x >= 0.0f && q.x <= static_cast<float>(width) && q.y >= 0.0f &&
         q.y <= static_cast<float>(height);
}

bool ScreenMetric::boxInView(Vec3 lo, Vec3 hi, float grow) const {
  return boxNearView(lo - Vec3(grow), hi + Vec3(grow), 0.0f);
}

std::array<ScreenMetric::Plane, 5> ScreenMetric::viewPlanes() const {
  const float ty = tanHalfFovY;
  const float tx = ty * static_cast<float>(width) / static_cast<float>(height);
  return {{{right - tx * forward, 0.0f},
           {-right - tx * forward, 0.0f},
           {up - ty * forward, 0.0f},
           {-up - ty * forward, 0.0f},
           {-forward, -nearDistance}}};
}

bool ScreenMetric::boxNearView(Vec3 lo, Vec3 hi, float distance) const {
  // The box is outside a plane dot(n, p - eye) > c when its corner nearest the inside is.
  for (const Plane& plane : viewPlanes()) {
    const Vec3 nearest(plane.n.x > 0.0f ? lo.x : hi.x, plane.n.y > 0.0f ? lo.y : hi.y,
                       plane.n.z > 0.0f ? lo.z : hi.z);
    if (glm::dot(plane.n, nearest - eye) > plane.c + distance * glm::length(plane.n)) return false;
  }
  return true;
}

}  // namespace meso
