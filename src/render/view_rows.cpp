// The theta_V rows a scene's frames can look a material's tables up at (view_rows.h).
#include "meso/render/view_rows.h"

#include "meso/appearance/declared_levels.h"
#include "meso/geometry/flat_faces.h"
#include "meso/render/surface_shader.h"
#include "meso/scene/camera_path.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

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
  for (const ScreenMetric::Plane& plane : s.viewPlanes()) {
    if (polygon.empty()) break;
    polygon = clipped(polygon, plane.n, s.eye, plane.c + grow * glm::length(plane.n));
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
// eye's height over the plane, the same for every p, so theta_V grows with the tile's tangential
// length of eye - p, |u - t w| with u and w the tile's images of eye - a and b - a: least at
// t = u.w / w.w, clamped to the segment.
float segmentMinimum(const TileMap& m, const Vec3& eye, const Vec3& a, const Vec3& b) {
  const Vec3 u3 = m.toTile(eye - a), w3 = m.toTile(b - a);
  const Vec2 u(u3.x, u3.y), w(w3.x, w3.y);
  const float ww = glm::dot(w, w);
  const float t = ww > 0.0f ? std::clamp(glm::dot(u, w) / ww, 0.0f, 1.0f) : 0.0f;
  return std::min(
      {tileThetaV(m, eye - (a + t * (b - a))), tileThetaV(m, eye - a), tileThetaV(m, eye - b)});
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

// Half a degree for rounding in the shader's own angles.
constexpr float kMargin = 0.5f * kPi / 180.0f;

// The smallest and largest factor by which the map scales tangent directions (the singular values
// of its tangential part).
std::pair<float, float> tangentialScales(const TileMap& m) {
  const Vec3 e1 = glm::normalize(m.a), e2 = glm::cross(m.N, e1);
  const float p = glm::dot(m.aDual, e1), q = glm::dot(m.aDual, e2), r = glm::dot(m.bDual, e1),
              t = glm::dot(m.bDual, e2);
  // Singular values of [[p, q], [r, t]].
  const float a = p * p + q * q + r * r + t * t, d = std::abs(p * t - q * r);
  const float root = std::sqrt(std::max(a * a - 4.0f * d * d, 0.0f));
  return {std::sqrt(std::max(0.5f * (a - root), 0.0f)), std::sqrt(0.5f * (a + root))};
}

// The steepest tilt of a level's normals in its tables' tile (TileRelief at `length` per unit of
// u, as the histograms trace it): its gradient sampled 8 times per shortest wavelength, then 10%
// steeper for the peaks between samples (a sinusoid's is 8% above its nearest sample's).
float steepestTilt(const ReliefLevel& level, float length) {
  const TileRelief tile(level, length);
  const float f = level.source->highestFrequency();
  const int n =
      std::clamp(static_cast<int>(std::ceil(8.0f * (std::isfinite(f) ? f : 128.0f))), 64, 1024);
  const float steepest = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, n), 0.0f,
      [&](const tbb::blocked_range<int>& rows, float m) {
        for (int j = rows.begin(); j < rows.end(); ++j)
          for (int i = 0; i < n; ++i) {
            const Vec2 g = tile.gradient((static_cast<float>(i) + 0.5f) / static_cast<float>(n),
                                         (static_cast<float>(j) + 0.5f) / static_cast<float>(n));
            m = std::max(m, glm::length(g));
          }
        return m;
      },
      [](float x, float y) { return std::max(x, y); });
  return std::isfinite(steepest) ? std::atan(1.1f * steepest) : 0.5f * kPi;
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
  // Faces in parallel: minima and maxima, the same whatever the order.
  struct Partial {
    float lo = 0.5f * kPi, hi = 0.0f;
    float sMin = std::numeric_limits<float>::infinity(), sMax = 0.0f;
    bool curved = false;
    Partial merged(const Partial& o) const {
      return {std::min(lo, o.lo), std::max(hi, o.hi), std::min(sMin, o.sMin),
              std::max(sMax, o.sMax), curved || o.curved};
    }
  };
  const auto faceAngles = [&](const LimitSurface& surface, int face, Partial& out) {
    // Most faces of a large ground no frame sees: their box (which holds the corners' limit
    // points), grown by the bound and a margin for rounding, misses every view.
    Vec3 lo, hi;
    if (!surface.faceBox(face, lo, hi)) return;
    const bool mayBeSeen = std::any_of(screens.begin(), screens.end(), [&](const ScreenMetric& s) {
      const float margin = 1e-4f * (glm::length(lo - s.eye) + glm::length(hi - s.eye));
      return s.boxNearView(lo, hi, bound + margin);
    });
    if (!mayBeSeen) return;
    if (!faceIsAffine(surface, face)) {
      out.curved = true;
      return;
    }
    const int n = surface.faceSize(face);
    std::vector<Vec3> polygon;
    Vec2 centre(0.0f);
    for (int k = 0; k < n; ++k) {
      const Vec2 st = surface.cornerSt(face, k);
      polygon.push_back(surface.evaluate(face, st).P);
      centre += st / static_cast<float>(n);
    }
    // The face's tile map only where a frame sees it (most faces of a large ground none does).
    std::optional<SurfacePoint> sp;
    TileMap m;
    for (const ScreenMetric& screen : screens) {
      const std::vector<Vec3> seen = inView(polygon, screen, bound);
      if (seen.size() < 3) continue;
      if (!sp) {
        sp = surface.evaluate(face, centre);
        m = tableTileMap(relief, relief.metricAt(sp->Pu, sp->Pv), sp->Pu, sp->Pv, sp->N);
        const auto [sMin, sMax] = tangentialScales(m);
        out.sMin = std::min(out.sMin, sMin);
        out.sMax = std::max(out.sMax, sMax);
      }
      // Raised relief lies within +-bound of the face along N: the eye moved the other way.
      for (const float h : {-bound, 0.0f, bound}) {
        const Vec3 eye = screen.eye - h * sp->N;
        for (const Vec3& p : seen) out.hi = std::max(out.hi, tileThetaV(m, eye - p));
        if (footInside(seen, sp->N, eye)) {
          out.lo = 0.0f;
          continue;
        }
        for (size_t i = 0; i < seen.size(); ++i)
          out.lo = std::min(out.lo, segmentMinimum(m, eye, seen[i], seen[(i + 1) % seen.size()]));
      }
    }
  };
  Partial total;
  for (const LimitSurface* surface : surfaces) {
    total = total.merged(tbb::parallel_reduce(
        tbb::blocked_range<int>(0, surface->numFaces()), Partial{},
        [&](const tbb::blocked_range<int>& faces, Partial p) {
          for (int face = faces.begin(); face < faces.end() && !p.curved; ++face)
            if (surface->hasLimitSurface(face)) faceAngles(*surface, face, p);
          return p;
        },
        [](const Partial& a, const Partial& b) { return a.merged(b); }));
    if (total.curved) return all;
  }
  const float lo = total.lo, hi = total.hi;
  if (!(lo <= hi) || !std::isfinite(lo) || !std::isfinite(hi)) return all;
  ViewAngles out;
  out.sMin = total.sMin;
  out.sMax = total.sMax;
  out.lo = std::max(lo - kMargin, 0.0f);
  out.hi = std::min(hi + kMargin, 0.5f * kPi);
  out.all = false;
  return out;
}

std::vector<ViewRows> levelViewRows(std::span<const LimitSurface* const> surfaces,
                                    const MaterialRelief& relief,
                                    std::span<const ScreenMetric> screens, float bound, int n,
                                    float thetaVMax) {
  std::vector<ViewRows> rows(relief.levels.size());
  const ViewAngles a = coarsestViewAngles(surfaces, relief, screens, bound);
  if (rows.empty() || a.all) return rows;
  rows[0] = viewRowsFor(a, n, thetaVMax);
  // A finer level's frame is tilted by the coarser levels' relief (raised, redistributed or bump
  // normals), and eq. (1) looks it up from the coarser level's visible normals: its rows widen by
  // the coarser levels' steepest tilt. Bounded where the tile map is the world's (one isotropic
  // class at the surfaces' own length), so that tilts and angles are the same in both.
  constexpr float kUnit = 0.01f;
  if (relief.metrics.size() != 1 || !relief.metrics[0].shape.identity() ||
      !(a.sMin >= 1.0f - kUnit && a.sMax <= 1.0f + kUnit))
    return rows;
  const float length = relief.metrics[0].lengthPerU;
  const float step = thetaVMax / static_cast<float>(n - 1);
  const auto lowest = [&](const ViewRows& r) { return r.all() ? 0.0f : step * r.first; };
  const auto highest = [&](const ViewRows& r) { return r.all() ? thetaVMax : step * r.last; };
  float tilt = 0.0f;  // of level i's frame: the coarser levels' steepest tilts, summed
  for (size_t i = 1; i < rows.size(); ++i) {
    const ReliefLevel& coarser = relief.levels[i - 1];
    float alpha = steepestTilt(coarser, length);
    if (coarser.partialSum) alpha = std::max(alpha, steepestTilt(*coarser.partialSum, length));
    tilt += alpha;
    if (!(tilt < 0.5f * kPi)) break;
    // The frame tilted by `tilt` sees theta_V within it of the surface's; its tangents stretch by
    // up to 1 / cos(tilt) along the slope, which lowers the tile's theta_V by up to that factor in
    // tan. A map within kUnit of the world's moves angles by under kMargin.
    ViewAngles w{a.lo - kMargin, a.hi + tilt + kMargin, false};
    w.lo = std::atan(std::cos(tilt) * std::tan(std::max(w.lo - tilt, 0.0f)));
    // Eq. (1): the coarser level's rows seen from its normals.
    w.lo = std::max(std::min(w.lo, lowest(rows[i - 1]) - alpha - kMargin), 0.0f);
    w.hi = std::min(std::max(w.hi, highest(rows[i - 1]) + alpha + kMargin), 0.5f * kPi);
    rows[i] = viewRowsFor(w, n, thetaVMax);
  }
  return rows;
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
