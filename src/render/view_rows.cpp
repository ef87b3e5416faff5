// The theta_V rows a scene's frames can look its coarsest tables up at (view_rows.h).
#include "meso/render/view_rows.h"

#include "meso/geometry/flat_faces.h"
#include "meso/render/surface_shader.h"
#include "meso/scene/camera_path.h"

#include <algorithm>
#include <cmath>

namespace meso {
namespace {

// The polygon's part where dot(n, p - eye) <= c (Sutherland-Hodgman against one plane).
std::vector<Vec3> clipped(const std::vector<Vec3>& polygon, const Vec3& n, const Vec3& eye,
                          float c) {
  std::vector<Vec3> out;
  const size_t m = polygon.size();
  for (size_t i = 0; i < m; ++i) {
    const Vec3& a = polygon[i];
    const Vec3& b = polygon[(i + 1) % m];
    const float da = glm::dot(n, a - eye) - c, db = glm::dot(n, b - eye) - c;
    if (da <= 0.0f) out.push_back(a);
    if ((da < 0.0f && db > 0.0f) || (da > 0.0f && db < 0.0f))
      out.push_back(a + da / (da - db) * (b - a));
  }
  return out;
}

// The face's part inside the screen's view, grown by `grow` (as ScreenMetric::boxNearView).
std::vector<Vec3> inView(std::vector<Vec3> polygon, const ScreenMetric& s, float grow) {
  const float ty = s.tanHalfFovY;
  const float tx = ty * static_cast<float>(s.width) / static_cast<float>(s.height);
  const Vec3 normals[5] = {s.right - tx * s.forward, -s.right - tx * s.forward,
                           s.up - ty * s.forward, -s.up - ty * s.forward, -s.forward};
  for (int k = 0; k < 5 && !polygon.empty(); ++k) {
    const float c = (k == 4 ? -s.nearDistance : 0.0f) + grow * glm::length(normals[k]);
    polygon = clipped(polygon, normals[k], s.eye, c);
  }
  return polygon;
}

// theta_V in tile space of the direction d from a surface point to the eye, on the side facing
// the eye (the shader flips N for a face seen from behind).
float tileThetaV(const TileMap& m, const Vec3& d) {
  const Vec3 t = m.toTile(d);
  return std::atan2(std::hypot(t.x, t.y), std::abs(t.z));
}

// The smallest tileThetaV(eye - p) over p on segment ab of the face's plane. N.(eye - p) is the
// eye's height over the plane, the same for every p, so theta_V grows with the map's tangential
// length of eye - p, a convex function of p: a ternary search finds its minimum.
float segmentMinimum(const TileMap& m, const Vec3& eye, const Vec3& a, const Vec3& b) {
  float lo = 0.0f, hi = 1.0f;
  const auto f = [&](float t) { return tileThetaV(m, eye - (a + t * (b - a))); };
  for (int i = 0; i < 60; ++i) {
    const float t1 = lo + (hi - lo) / 3.0f, t2 = hi - (hi - lo) / 3.0f;
    if (f(t1) <= f(t2))
      hi = t2;
    else
      lo = t1;
  }
  return std::min({f(lo), f(0.0f), f(1.0f)});
}

// Whether the eye's foot on the face's plane lies in the convex polygon (there theta_V is 0).
bool footInside(const std::vector<Vec3>& polygon, const Vec3& N, const Vec3& eye) {
  const Vec3 foot = eye - glm::dot(eye - polygon[0], N) * N;
  int sign = 0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Vec3& a = polygon[i];
    const Vec3& b = polygon[(i + 1) % polygon.size()];
    const float s = glm::dot(glm::cross(b - a, foot - a), N);
    const int here = s > 0.0f ? 1 : s < 0.0f ? -1 : 0;
    if (here == 0) continue;
    if (sign != 0 && here != sign) return false;
    sign = here;
  }
  return true;
}

}  // namespace

std::vector<CameraSettings> sceneCameras(const Scene& scene) {
  if (scene.path.keys.empty() || scene.path.frames <= 0) return {scene.camera};
  const CameraPath path(scene.path.keys);
  std::vector<CameraSettings> out;
  for (int f = 0; f < scene.path.frames; ++f)
    out.push_back(path.frame(f, scene.path.frames, scene.camera));
  return out;
}

ViewAngles coarsestViewAngles(std::span<const LimitSurface* const> surfaces,
                              const MaterialRelief& relief, std::span<const ScreenMetric> screens,
                              float bound) {
  ViewAngles all;
  if (relief.metrics.empty() || screens.empty() || !std::isfinite(bound)) return all;
  float lo = 0.5f * kPi, hi = 0.0f;
  for (const LimitSurface* surface : surfaces) {
    const std::vector<uint8_t> flat = affineFaces(*surface);
    for (int face = 0; face < surface->numFaces(); ++face) {
      if (!surface->hasLimitSurface(face)) continue;
      if (!flat[face]) return all;
      const int n = surface->faceSize(face);
      std::vector<Vec3> polygon;
      Vec2 centre(0.0f);
      for (int k = 0; k < n; ++k) {
        const Vec2 st = surface->cornerSt(face, k);
        polygon.push_back(surface->evaluate(face, st).P);
        centre += st / static_cast<float>(n);
      }
      const SurfacePoint sp = surface->evaluate(face, centre);
      const TileMap m = tableTileMap(relief, relief.metricAt(sp.Pu, sp.Pv), sp.Pu, sp.Pv, sp.N);
      for (const ScreenMetric& screen : screens) {
        const std::vector<Vec3> seen = inView(polygon, screen, bound);
        if (seen.size() < 3) continue;
        // Raised relief lies within +-bound of the face along N: the eye moved the other way.
        for (const float h : {-bound, 0.0f, bound}) {
          const Vec3 eye = screen.eye - h * sp.N;
          for (const Vec3& p : seen) hi = std::max(hi, tileThetaV(m, eye - p));
          if (footInside(seen, sp.N, eye)) {
            lo = 0.0f;
            continue;
          }
          for (size_t i = 0; i < seen.size(); ++i)
            lo = std::min(lo, segmentMinimum(m, eye, seen[i], seen[(i + 1) % seen.size()]));
        }
      }
    }
  }
  if (!(lo <= hi) || !std::isfinite(lo) || !std::isfinite(hi)) return all;
  // Half a degree for rounding in the shader's own angles.
  constexpr float kMargin = 0.5f * kPi / 180.0f;
  return {std::max(lo - kMargin, 0.0f), std::min(hi + kMargin, 0.5f * kPi), false};
}

ViewRows viewRowsFor(const ViewAngles& angles, int n, float thetaVMax) {
  if (angles.all || n < 2 || !(thetaVMax > 0.0f)) return {};
  const float step = thetaVMax / static_cast<float>(n - 1);
  const int first = std::clamp(static_cast<int>(std::floor(angles.lo / step)), 0, n - 1);
  const int last = angles.hi >= thetaVMax
                       ? n - 1
                       : std::clamp(static_cast<int>(std::ceil(angles.hi / step)), first, n - 1);
  if (first == 0 && last == n - 1) return {};
  return {first, last};
}

}  // namespace meso
