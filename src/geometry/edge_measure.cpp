// The rate of each mesh edge, measured once (edge_measure.h; shared/DESIGN.md section 5).
#include "edge_measure.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace meso {

namespace {

using OpenSubdiv::Far::ConstIndexArray;

// Pixel length of the limit edge from a few points along it, and the segments a polyline needs to
// stay within `tolerance` pixels of it: a chord's deviation from a smooth curve falls as 1/n^2 with
// n segments. Deviations are scaled by the pixels per unit at their depth, which is conservative
// (it ignores foreshortening).
// `lo`, `hi`: the box of those points.
void measureLimitEdge(const LimitSurface& surface, const ScreenMetric& screen,
                      EdgeRateTessellator::Use owner, const DicingSettings& s, EdgeMeasure& m,
                      Vec3& lo, Vec3& hi) {
  const DicingMetric metric = s.metric;
  const float tolerance = s.coarseTolerance;
  constexpr int kSegments = 4;
  const LimitSurface::Impl& impl = surface.impl();
  const int n = surface.faceSize(owner.face);
  const Vec2 s0 = impl.cornerSt(owner.face, owner.corner);
  const Vec2 s1 = impl.cornerSt(owner.face, (owner.corner + 1) % n);
  Vec3 P[kSegments + 1];
  Vec3 midN(0.0f);
  lo = Vec3(std::numeric_limits<float>::infinity()), hi = -lo;
  for (int k = 0; k <= kSegments; ++k) {
    const SurfacePoint sp = surface.evaluate(owner.face, glm::mix(s0, s1, float(k) / kSegments));
    P[k] = sp.P;
    if (2 * k == kSegments) midN = sp.N;
    lo = glm::min(lo, P[k]);
    hi = glm::max(hi, P[k]);
  }
  if (s.acrossViewCap < 1.0f)
    m.capScale =
        acrossViewCapScale(screen, P[kSegments / 2], midN, P[kSegments] - P[0], s.acrossViewCap);
  float length = 0.0f, deviationPx = 0.0f;
  for (int k = 0; k < kSegments; ++k)
    length += metric == DicingMetric::Projected ? screen.projectedLength(P[k], P[k + 1])
                                                : screen.footprintLength(P[k], P[k + 1]);
  if (metric == DicingMetric::Isotropic) {
    for (int k = 0; k < kSegments; ++k) m.worldLength += glm::length(P[k + 1] - P[k]);
    for (int k = 0; k <= kSegments; ++k)
      if (screen.pointInView(P[k])) m.density = std::max(m.density, screen.pixelDensity(P[k]));
    if (!std::isfinite(m.worldLength * m.density)) m.worldLength = m.density = 0.0f;
  }
  for (int k = 1; k < kSegments; ++k) {
    const float z = screen.depth(P[k]);
    if (!(z >= screen.nearDistance)) continue;
    const Vec3 chord = glm::mix(P[0], P[kSegments], float(k) / kSegments);
    deviationPx = std::max(deviationPx, glm::length(P[k] - chord) * screen.pixelsPerUnit(z));
  }
  m.lengthPx = std::isfinite(length) ? length : 0.0f;
  m.coarseSegments = std::isfinite(deviationPx) ? std::sqrt(deviationPx / tolerance) : 0.0f;
}

// Bfr spaces a quad's interior points evenly, with the mean rate of opposite edges, so the rate
// an edge's own points ask for leaves the near part of a face that recedes in depth too coarse.
// With the isotropic metric a diced edge is therefore sized by the densest point in view on any
// diced face it bounds: its world length times that face's largest pixelDensity (sampled on the
// face's edges). This over-dices the far part of deep faces, which are few: the ones near the eye.
void spreadFaceDensity(const LimitSurface::Impl::Topology& base, const FaceDicing& faces,
                       const std::vector<char>& inView, std::vector<EdgeMeasure>& measures) {
  std::vector<float> faceDensity(inView.size(), 0.0f);
  for (size_t f = 0; f < inView.size(); ++f) {
    if (!inView[f] || (!faces.needsDicing.empty() && !faces.needsDicing[f])) continue;
    for (int e : base.faceEdges(static_cast<int>(f)))
      faceDensity[f] = std::max(faceDensity[f], measures[e].density);
  }
  for (size_t e = 0; e < measures.size(); ++e) {
    EdgeMeasure& m = measures[e];
    if (m.kind != EdgeMeasure::Diced) continue;
    for (int f : base.edgeFaces(static_cast<int>(e)))
      m.lengthPx = std::max(m.lengthPx, m.worldLength * faceDensity[f]);
  }
}

}  // namespace

float acrossViewCapScale(const ScreenMetric& screen, Vec3 p, Vec3 N, Vec3 dir, float across) {
  const Vec3 toEye = screen.eye - p;
  const float eyeLength = glm::length(toEye), dirLength = glm::length(dir);
  if (!(eyeLength > 0.0f) || !(dirLength > 0.0f) || !std::isfinite(eyeLength * dirLength))
    return 1.0f;
  const Vec3 w = toEye / eyeLength;
  const Vec3 tangent = w - glm::dot(w, N) * N;  // |tangent| = sin(theta_V) for a unit N
  const float sin2 = glm::dot(tangent, tangent);
  if (!(sin2 > 1e-12f) || !(sin2 <= 1.0f + 1e-4f)) return 1.0f;
  const float c = glm::dot(dir / dirLength, tangent) / std::sqrt(sin2);
  const float scale = 1.0f - (1.0f - across) * (1.0f - std::min(c * c, 1.0f)) * sin2;
  return std::isfinite(scale) ? std::clamp(scale, std::min(across, 1.0f), 1.0f) : 1.0f;
}

bool faceInView(const LimitSurface& surface, const ScreenMetric& screen, int face, float grow) {
  Vec3 lo, hi;
  return surface.faceBox(face, lo, hi) && screen.boxInView(lo, hi, grow);
}

std::vector<char> facesInView(const LimitSurface& surface, const ScreenMetric& screen, float grow,
                              std::vector<float>& distance) {
  std::vector<char> inView(surface.numFaces(), 0);
  distance.assign(inView.size(), 0.0f);
  tbb::parallel_for(0, surface.numFaces(), [&](int f) {
    Vec3 lo, hi;
    if (!surface.faceBox(f, lo, hi)) return;
    inView[f] = faceInView(surface, screen, f, grow);
    const float d = boxDistance(screen.eye, lo - Vec3(grow), hi + Vec3(grow));
    distance[f] = std::isfinite(d) ? d : 0.0f;
  });
  return inView;
}

std::vector<char> facesKept(const LimitSurface& surface, const ScreenMetric& screen, float grow,
                            const std::vector<char>& inView,
                            const DicingSettings::ShadowCasters& casters) {
  std::vector<char> keep(inView);
  tbb::parallel_for(0, surface.numFaces(), [&](int f) {
    Vec3 lo, hi;
    if (keep[f] || !surface.faceBox(f, lo, hi)) return;
    // In view but nearer than the near plane, which rays from the eye do not have.
    keep[f] = screen.boxInView(lo, hi, grow + 2.0f * screen.nearDistance) ||
              mayShadowView(lo - Vec3(grow), hi + Vec3(grow), screen, casters);
  });
  return keep;
}

std::vector<EdgeMeasure> measureEdges(const LimitSurface& surface,
                                      const EdgeRateTessellator& engine, const ScreenMetric& screen,
                                      const DicingSettings& settings, const FaceDicing& faces,
                                      const std::vector<char>& inView,
                                      const std::vector<float>& faceDistance, float bound) {
  const LimitSurface::Impl::Topology& base = surface.impl().topology;
  std::vector<EdgeMeasure> measures(engine.numEdges());
  tbb::parallel_for(0, engine.numEdges(), [&](int e) {
    EdgeMeasure& m = measures[e];
    const ConstIndexArray edgeFaces = base.edgeFaces(e);
    if (std::none_of(edgeFaces.begin(), edgeFaces.end(), [&](int f) { return inView[f]; })) return;
    m.distance = std::numeric_limits<float>::infinity();
    for (int f : edgeFaces)
      if (inView[f]) m.distance = std::min(m.distance, faceDistance[f]);
    Vec3 lo, hi;
    measureLimitEdge(surface, screen, engine.edgeOwner(e), settings, m, lo, hi);
    const float grow = bound + 0.5f * glm::length(hi - lo);
    m.kind = EdgeMeasure::Coarse;
    bool uncapped = false;
    for (int f : edgeFaces) {
      if (!inView[f]) continue;
      if (!faces.needsDicing.empty() && !faces.needsDicing[f]) continue;
      if (!faces.raisesBox(f, screen.eye, lo, hi, grow)) continue;
      m.kind = EdgeMeasure::Diced;
      const int cap = faces.texelCap.empty() ? 0 : faces.texelCap[f];
      uncapped = uncapped || cap == 0;
      m.cap = std::max(m.cap, cap);
      if (!faces.texelFloor.empty()) m.floor = std::max(m.floor, faces.texelFloor[f]);
    }
    if (uncapped) m.cap = 0;
  });
  if (settings.metric == DicingMetric::Isotropic) spreadFaceDensity(base, faces, inView, measures);
  return measures;
}

int edgeRate(const EdgeMeasure& m, const DicingSettings& s, const CapCoarsening& cap) {
  if (m.kind == EdgeMeasure::Culled) return 1;
  const float coarsening = cap.factor(m.distance);
  int rate = toRate(m.coarseSegments / coarsening, s.maxEdgeRate);
  if (m.kind == EdgeMeasure::Diced) {
    const int limit = m.cap > 0 ? std::min(m.cap, s.maxEdgeRate) : s.maxEdgeRate;
    // The pixel rate stops at the cap scaled across the view; the floor (a texel image's masking)
    // at the whole cap.
    const int scaled = m.cap > 0 ? scaledCap(limit, m.capScale) : limit;
    rate = std::max(rate, toRate(m.lengthPx / (s.dicingRate * coarsening), scaled));
    rate = std::max(rate, toRate(static_cast<float>(m.floor) / coarsening, limit));
  }
  return rate;
}

}  // namespace meso
