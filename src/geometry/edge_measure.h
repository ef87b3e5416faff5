// Private to src/geometry: what the rate of each mesh edge depends on, measured once per frame
// (pixel length of its limit edge, the segments that follow the limit surface, the texel cap and
// floor of the diced faces it bounds), and its rate for any coarsening of the micropolygon cap.
#pragma once

#include "cap_coarsening.h"
#include "limit_surface_impl.h"
#include "meso/geometry/adaptive_tessellation.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace meso {

// What the rate of one mesh edge depends on, measured once; rates for any coarsening follow.
struct EdgeMeasure {
  enum Kind : char { Culled, Coarse, Diced };
  Kind kind = Culled;
  float lengthPx = 0.0f;        // pixel length of the limit edge, by DicingSettings::metric
  float worldLength = 0.0f;     // isotropic metric: world length of the limit edge
  float density = 0.0f;         // isotropic metric: largest pixelDensity of its points in view
  float coarseSegments = 0.0f;  // segments that follow the limit surface to the tolerance
  int cap = 0;                  // largest useful rate of the diced neighbours, 0 = none
  int floor = 0;                // least rate the diced neighbours ask for, 0 = none
  float capScale = 1.0f;        // share of `cap` the edge keeps (acrossViewCapScale)
  // The nearest distance from the eye of the faces in view it bounds (their patch hulls grown by
  // the displacement bound): the cap coarsens it by CapCoarsening::factor of this, so no edge of a
  // face that reaches nearer than CapCoarsening::beyond is coarsened.
  float distance = 0.0f;
};

// DicingSettings::acrossViewCap at a point p with normal N for a direction `dir` in the surface:
// 1 - (1 - across) (1 - c^2) sin^2(theta_V), c the cosine between dir and the view's direction in
// the tangent plane. 1 where anything is undefined (a degenerate direction or normal).
float acrossViewCapScale(const ScreenMetric& screen, Vec3 p, Vec3 N, Vec3 dir, float across);

// `cap` scaled by `scale`, at least 1; 0 (no cap) stays 0.
inline int scaledCap(int cap, float scale) {
  if (cap <= 0 || !(scale < 1.0f)) return cap;
  return std::max(1, static_cast<int>(std::ceil(static_cast<float>(cap) * scale)));
}

// faceInView of every face, grown by the displacement bound. `distance`: from the eye to that
// box, a lower bound of the distance of the face's displaced points.
std::vector<char> facesInView(const LimitSurface& surface, const ScreenMetric& screen, float grow,
                              std::vector<float>& distance);

// Per face: 1 where it is in view (inView) or, out of view, may block a shadow ray of the frame
// (mayShadowView with its box grown by `grow`); the faces the frame's geometry needs.
std::vector<char> facesKept(const LimitSurface& surface, const ScreenMetric& screen, float grow,
                            const std::vector<char>& inView,
                            const DicingSettings::ShadowCasters& casters);

// An edge is diced for the faces in view that need dicing and may raise relief near it: its
// points' box grown by the displacement bound plus half its diagonal (the limit edge between the
// points sags by far less). `bound` is the displacement bound.
std::vector<EdgeMeasure> measureEdges(const LimitSurface& surface,
                                      const EdgeRateTessellator& engine, const ScreenMetric& screen,
                                      const DicingSettings& settings, const FaceDicing& faces,
                                      const std::vector<char>& inView,
                                      const std::vector<float>& faceDistance, float bound);

// The rate of an edge under the cap's coarsening (CapCoarsening{}: as asked).
int edgeRate(const EdgeMeasure& m, const DicingSettings& s, const CapCoarsening& cap);

}  // namespace meso
