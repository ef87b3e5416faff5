#include "meso/scene/camera_path.h"

#include "meso/core/error.h"

#include <algorithm>
#include <cmath>

namespace meso {
namespace {

// Catmull-Rom tangent at key i for non-uniform times; one-sided at the ends.
template <typename T, typename Get>
T tangent(const std::vector<CameraKeyframe>& k, size_t i, Get get) {
  const size_t a = i == 0 ? 0 : i - 1, b = std::min(i + 1, k.size() - 1);
  if (a == b) return get(k[i]) * 0.0f;
  return (get(k[b]) - get(k[a])) / (k[b].time - k[a].time);
}

template <typename T, typename Get>
T hermite(const std::vector<CameraKeyframe>& k, size_t i, float s, Get get) {
  const float h = k[i + 1].time - k[i].time;
  const float s2 = s * s, s3 = s2 * s;
  const T m0 = tangent<T>(k, i, get) * h, m1 = tangent<T>(k, i + 1, get) * h;
  return (2 * s3 - 3 * s2 + 1) * get(k[i]) + (s3 - 2 * s2 + s) * m0 +
         (-2 * s3 + 3 * s2) * get(k[i + 1]) + (s3 - s2) * m1;
}

}  // namespace

CameraPath::CameraPath(std::vector<CameraKeyframe> keys) : keys_(std::move(keys)) {
  if (keys_.empty()) throw Error("camera path: needs at least one keyframe");
  for (size_t i = 1; i < keys_.size(); ++i)
    if (!(keys_[i].time > keys_[i - 1].time))
      throw Error("camera path: keyframe times must strictly increase (keyframe " +
                  std::to_string(i + 1) + " has time " + std::to_string(keys_[i].time) + ")");
}

CameraKeyframe CameraPath::at(float t) const {
  if (keys_.size() == 1 || !(t > keys_.front().time)) return keys_.front();
  if (t >= keys_.back().time) return keys_.back();
  const auto it = std::upper_bound(keys_.begin(), keys_.end(), t,
                                   [](float v, const CameraKeyframe& k) { return v < k.time; });
  const size_t i = static_cast<size_t>(it - keys_.begin()) - 1;
  const float s = (t - keys_[i].time) / (keys_[i + 1].time - keys_[i].time);
  CameraKeyframe out;
  out.time = t;
  out.position = hermite<Vec3>(keys_, i, s, [](const CameraKeyframe& k) { return k.position; });
  out.lookAt = hermite<Vec3>(keys_, i, s, [](const CameraKeyframe& k) { return k.lookAt; });
  const Vec3 up = hermite<Vec3>(keys_, i, s, [](const CameraKeyframe& k) { return k.up; });
  out.up = glm::length(up) > 1e-6f ? glm::normalize(up) : keys_[i].up;
  out.fovY = hermite<float>(keys_, i, s, [](const CameraKeyframe& k) { return k.fovY; });
  out.fovY = std::clamp(out.fovY, 1e-3f, 179.0f);
  return out;
}

CameraSettings CameraPath::frame(int i, int n, const CameraSettings& base) const {
  const float f = n > 1 ? static_cast<float>(i) / static_cast<float>(n - 1) : 0.0f;
  const CameraKeyframe k = at(startTime() + f * (endTime() - startTime()));
  CameraSettings c = base;
  c.position = k.position;
  c.lookAt = k.lookAt;
  c.up = k.up;
  c.fovY = k.fovY;
  return c;
}

}  // namespace meso
