// View-dependent dicing of a limit surface into displaced micropolygons (Becker & Max 1993 section
// 2.3: vertices displaced along the normal; shared/DESIGN.md section 5: edges at most dicing_rate
// pixels where a level may be displaced, elsewhere just fine enough to follow the limit surface,
// rates shared between neighbouring patches).
#include "meso/geometry/adaptive_tessellation.h"

#include "cap_coarsening.h"
#include "face_split.h"
#include "limit_surface_impl.h"
#include "meso/core/error.h"
#include "meso/core/timer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

namespace meso {

namespace {

using OpenSubdiv::Far::ConstIndexArray;

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
  // The nearest distance from the eye of the faces in view it bounds (their patch hulls grown by
  // the displacement bound): the cap coarsens it by CapCoarsening::factor of this, so no edge of a
  // face that reaches nearer than CapCoarsening::beyond is coarsened.
  float distance = 0.0f;
};

void validate(const LimitSurface& surface, const DicingSettings& s, const FaceDicing& faces) {
  if (!(s.dicingRate > 0.0f) || !std::isfinite(s.dicingRate))
    throw Error("dicing rate must be a positive number of pixels (got " +
                std::to_string(s.dicingRate) + ")");
  if (s.maxEdgeRate < 1 || s.maxEdgeRate > std::numeric_limits<short>::max())
    throw Error("maximum edge rate must be in [1, 32767] (got " + std::to_string(s.maxEdgeRate) +
                ")");
  if (!(s.coarseTolerance > 0.0f))
    throw Error("coarse tolerance must be a positive number of pixels");
  if (s.maxMicropolygons < 1) throw Error("micropolygon cap must be at least 1");
  const size_t n = static_cast<size_t>(surface.numFaces());
  if (!faces.needsDicing.empty() && faces.needsDicing.size() != n)
    throw Error("needsDicing has " + std::to_string(faces.needsDicing.size()) + " entries for " +
                std::to_string(n) + " faces");
  if (!faces.texelCap.empty() && faces.texelCap.size() != n)
    throw Error("texelCap has " + std::to_string(faces.texelCap.size()) + " entries for " +
                std::to_string(n) + " faces");
  if (!faces.texelFloor.empty() && faces.texelFloor.size() != n)
    throw Error("texelFloor has " + std::to_string(faces.texelFloor.size()) + " entries for " +
                std::to_string(n) + " faces");
  if (!faces.raiseDistance.empty() && faces.raiseDistance.size() != n)
    throw Error("raiseDistance has " + std::to_string(faces.raiseDistance.size()) +
                " entries for " + std::to_string(n) + " faces");
  for (float d : faces.raiseDistance)
    if (!(d >= 0.0f)) throw Error("raise distances must be >= 0 (infinity: everywhere)");
  for (int cap : faces.texelCap)
    if (cap < 0) throw Error("texel caps must be 0 (none) or positive rates");
  for (int floor : faces.texelFloor)
    if (floor < 0) throw Error("texel floors must be 0 (none) or positive rates");
}

// A face is in view when the box of its patch points, grown by the displacement bound, is: the
// limit patch lies in the convex hull of its patch points (B-spline and Gregory bases are
// non-negative and sum to one), so the box is conservative. `distance`: from the eye to that box,
// a lower bound of the distance of the face's displaced points.
std::vector<char> facesInView(const LimitSurface& surface, const ScreenMetric& screen, float grow,
                              std::vector<float>& distance) {
  const LimitSurface::Impl& impl = surface.impl();
  std::vector<char> inView(surface.numFaces(), 0);
  distance.assign(inView.size(), 0.0f);
  tbb::parallel_for(0, surface.numFaces(), [&](int f) {
    const LimitSurface::Impl::Face& face = impl.faces[f];
    if (!face.surface.IsValid()) return;
    Vec3 lo(std::numeric_limits<float>::infinity()), hi(-lo);
    const float* p = &impl.patchPoints[face.patchOffset];
    for (int i = 0; i < face.surface.GetNumPatchPoints(); ++i, p += 3) {
      lo = glm::min(lo, Vec3(p[0], p[1], p[2]));
      hi = glm::max(hi, Vec3(p[0], p[1], p[2]));
    }
    inView[f] = screen.boxInView(lo, hi, grow);
    const float d = boxDistance(screen.eye, lo - Vec3(grow), hi + Vec3(grow));
    distance[f] = std::isfinite(d) ? d : 0.0f;
  });
  return inView;
}

// Pixel length of the limit edge from a few points along it, and the segments a polyline needs to
// stay within `tolerance` pixels of it: a chord's deviation from a smooth curve falls as 1/n^2 with
// n segments. Deviations are scaled by the pixels per unit at their depth, which is conservative
// (it ignores foreshortening).
// `lo`, `hi`: the box of those points.
void measureLimitEdge(const LimitSurface& surface, const ScreenMetric& screen,
                      EdgeRateTessellator::Use owner, DicingMetric metric, float tolerance,
                      EdgeMeasure& m, Vec3& lo, Vec3& hi) {
  constexpr int kSegments = 4;
  const LimitSurface::Impl& impl = surface.impl();
  const int n = surface.faceSize(owner.face);
  const Vec2 s0 = impl.cornerSt(owner.face, owner.corner);
  const Vec2 s1 = impl.cornerSt(owner.face, (owner.corner + 1) % n);
  Vec3 P[kSegments + 1];
  lo = Vec3(std::numeric_limits<float>::infinity()), hi = -lo;
  for (int k = 0; k <= kSegments; ++k) {
    P[k] = surface.evaluate(owner.face, glm::mix(s0, s1, float(k) / kSegments)).P;
    lo = glm::min(lo, P[k]);
    hi = glm::max(hi, P[k]);
  }
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
void spreadFaceDensity(const OpenSubdiv::Far::TopologyLevel& base, const FaceDicing& faces,
                       const std::vector<char>& inView, std::vector<EdgeMeasure>& measures) {
  std::vector<float> faceDensity(inView.size(), 0.0f);
  for (size_t f = 0; f < inView.size(); ++f) {
    if (!inView[f] || (!faces.needsDicing.empty() && !faces.needsDicing[f])) continue;
    for (int e : base.GetFaceEdges(static_cast<int>(f)))
      faceDensity[f] = std::max(faceDensity[f], measures[e].density);
  }
  for (size_t e = 0; e < measures.size(); ++e) {
    EdgeMeasure& m = measures[e];
    if (m.kind != EdgeMeasure::Diced) continue;
    for (int f : base.GetEdgeFaces(static_cast<int>(e)))
      m.lengthPx = std::max(m.lengthPx, m.worldLength * faceDensity[f]);
  }
}

// An edge is diced for the faces in view that need dicing and may raise relief near it: its
// points' box grown by the displacement bound plus half its diagonal (the limit edge between the
// points sags by far less).
std::vector<EdgeMeasure> measureEdges(const LimitSurface& surface,
                                      const EdgeRateTessellator& engine, const ScreenMetric& screen,
                                      const DicingSettings& settings, const FaceDicing& faces,
                                      const std::vector<char>& inView,
                                      const std::vector<float>& faceDistance, float bound) {
  const OpenSubdiv::Far::TopologyLevel& base = surface.impl().refiner->GetLevel(0);
  std::vector<EdgeMeasure> measures(engine.numEdges());
  tbb::parallel_for(0, engine.numEdges(), [&](int e) {
    EdgeMeasure& m = measures[e];
    const ConstIndexArray edgeFaces = base.GetEdgeFaces(e);
    if (std::none_of(edgeFaces.begin(), edgeFaces.end(), [&](int f) { return inView[f]; })) return;
    m.distance = std::numeric_limits<float>::infinity();
    for (int f : edgeFaces)
      if (inView[f]) m.distance = std::min(m.distance, faceDistance[f]);
    Vec3 lo, hi;
    measureLimitEdge(surface, screen, engine.edgeOwner(e), settings.metric,
                     settings.coarseTolerance, m, lo, hi);
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

// ceil(x) clamped to [1, limit]; NaN gives 1.
int toRate(float x, int limit) {
  if (!(x > 1.0f)) return 1;
  return static_cast<int>(std::min(std::ceil(x), static_cast<float>(limit)));
}

// The rate of an edge under the cap's coarsening (CapCoarsening{}: as asked).
int edgeRate(const EdgeMeasure& m, const DicingSettings& s, const CapCoarsening& cap) {
  if (m.kind == EdgeMeasure::Culled) return 1;
  const float coarsening = cap.factor(m.distance);
  int rate = toRate(m.coarseSegments / coarsening, s.maxEdgeRate);
  if (m.kind == EdgeMeasure::Diced) {
    const int limit = m.cap > 0 ? std::min(m.cap, s.maxEdgeRate) : s.maxEdgeRate;
    rate = std::max(rate, toRate(m.lengthPx / (s.dicingRate * coarsening), limit));
    rate = std::max(rate, toRate(static_cast<float>(m.floor) / coarsening, limit));
  }
  return rate;
}

// What one surface measured once; its rates for any cap coarsening follow (ratesFor).
struct SurfaceDicing {
  const AdaptiveSurface* input = nullptr;
  std::vector<char> inView;
  std::unique_ptr<EdgeRateTessellator> engine;
  std::vector<EdgeMeasure> measures;
  SplitPlan plan;
  float farthest = 0.0f;  // of a unit the cap may coarsen: an edge not culled or a split cell
};

SurfaceDicing measureSurface(const AdaptiveSurface& in, const ScreenMetric& screen,
                             const DicingSettings& settings) {
  SurfaceDicing d;
  d.input = &in;
  const float bound = in.displacement ? std::max(in.displacement->bound(), 0.0f) : 0.0f;
  std::vector<float> faceDistance;
  d.inView = facesInView(*in.surface, screen, bound, faceDistance);
  d.engine = std::make_unique<EdgeRateTessellator>(*in.surface);
  d.engine->setGridsOnly(settings.gridsOnly);
  d.measures = measureEdges(*in.surface, *d.engine, screen, settings, in.faces, d.inView,
                            faceDistance, bound);
  if (settings.splitFaces)
    d.plan = planSplits(*in.surface, screen, settings, in.faces, d.inView, bound);
  d.farthest = farthestCell(d.plan);
  for (const EdgeMeasure& m : d.measures)
    if (m.kind != EdgeMeasure::Culled) d.farthest = std::max(d.farthest, m.distance);
  return d;
}

// One surface's rates for a cap coarsening: edges, splits and the triangles they give.
struct RateChoice {
  std::vector<int> rates;
  std::vector<FaceSplit> splits;
  int facesSplit = 0;
  int maxRate = 1;
  size_t count = 0;
};

RateChoice ratesFor(SurfaceDicing& d, const DicingSettings& s, const CapCoarsening& cap) {
  RateChoice c;
  c.rates.resize(d.measures.size());
  for (size_t e = 0; e < d.measures.size(); ++e) {
    c.rates[e] = edgeRate(d.measures[e], s, cap);
    c.maxRate = std::max(c.maxRate, c.rates[e]);
  }
  c.splits = splitsFor(*d.input->surface, d.plan, c.rates, s, cap, c.facesSplit);
  c.count = d.engine->countFacets(c.rates, c.splits);
  return c;
}

// Every surface's rates for one cap coarsening, and their sums.
struct FrameChoice {
  CapCoarsening cap;
  std::vector<RateChoice> surfaces;
  size_t count = 0;
  int maxRate = 1;
  size_t asked = 0;  // the triangles without the cap (chooseRates)
};

FrameChoice ratesFor(std::vector<SurfaceDicing>& dicings, const DicingSettings& s,
                     const CapCoarsening& cap) {
  FrameChoice c;
  c.cap = cap;
  for (SurfaceDicing& d : dicings) {
    c.surfaces.push_back(ratesFor(d, s, cap));
    c.count += c.surfaces.back().count;
    c.maxRate = std::max(c.maxRate, c.surfaces.back().maxRate);
  }
  return c;
}

std::string capWarning(const DicingSettings& s, const FrameChoice& frame, size_t count,
                       float farthest) {
  const CapCoarsening& cap = frame.cap;
  const std::string where =
      cap.beyond >= cap.floor
          ? fmt::format(
                "as asked nearer than {:.4g} units from the eye, coarsened by distance / "
                "{:.4g} beyond ({:.3g}x at its farthest, {:.4g} units)",
                cap.beyond, cap.beyond, cap.factor(farthest), farthest)
          : fmt::format(
                "every edge rate coarsened by at least {:.3g}x, by distance / {:.4g} "
                "beyond {:.4g} units ({:.3g}x at its farthest, {:.4g} units)",
                cap.factor(0.0f), cap.beyond, cap.floor, cap.factor(farthest), farthest);
  return fmt::format(
      "adaptive tessellation: {} micropolygons would exceed the cap of {}; dicing (rate {:.3g} "
      "px) {}, giving {}{}{}",
      frame.asked, s.maxMicropolygons, s.dicingRate, where, count,
      frame.surfaces.size() > 1 ? fmt::format(" of the frame's {}", frame.count) : "",
      frame.count > s.maxMicropolygons ? ", still over the cap at rate 1" : "");
}

// Rates for every surface: as asked if their triangles together fit under the cap, else
// coarsened farthest first (CapCoarsening) with one D for all and about the largest that fits:
// D halves from the farthest unit's distance until the count fits (or every rate is 1), then
// log D is bisected to 1/256 of an octave. The split faces' sub-quads are coarsened with the edges
// and counted with them.
FrameChoice chooseRates(std::vector<SurfaceDicing>& dicings, const ScreenMetric& screen,
                        const DicingSettings& s) {
  FrameChoice best = ratesFor(dicings, s, CapCoarsening{});
  const size_t asked = best.asked = best.count;
  if (best.count <= s.maxMicropolygons || best.maxRate == 1) return best;
  const float floor = std::max(screen.nearDistance, 1e-6f);
  float fails = floor;  // D = the farthest unit's distance coarsens nothing
  for (const SurfaceDicing& d : dicings) fails = std::max(fails, d.farthest);
  for (int k = 0; k < 128; ++k) {
    best = ratesFor(dicings, s, {.beyond = 0.5f * fails, .floor = floor});
    if (best.count <= s.maxMicropolygons || best.maxRate == 1) break;
    fails = best.cap.beyond;
  }
  for (int k = 0; k < 8 && best.count <= s.maxMicropolygons; ++k) {
    const float mid = std::sqrt(best.cap.beyond * fails);
    FrameChoice trial = ratesFor(dicings, s, {.beyond = mid, .floor = floor});
    if (trial.count <= s.maxMicropolygons)
      best = std::move(trial);
    else
      fails = mid;
  }
  best.asked = asked;
  return best;
}

// Triangles none of whose corners is in view: the mesh's, and those only its grids hold.
size_t countOffScreen(const TessellatedMesh& m, const std::vector<TriangleGrid>& grids,
                      const ScreenMetric& screen) {
  const size_t inGrids = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, grids.size()), size_t{0},
      [&](const tbb::blocked_range<size_t>& range, size_t count) {
        for (size_t k = range.begin(); k != range.end(); ++k) {
          const TriangleGrid& g = grids[k];
          if (g.firstTriangle != TriangleGrid::kNotInMesh) continue;
          const auto seen = [&](int i, int j) {
            return screen.pointInView(m.positions[g.firstVertex + size_t(j) * g.width + i]);
          };
          for (int j = 0; j + 1 < g.height; ++j)
            for (int i = 0; i + 1 < g.width; ++i) {
              const bool p01 = seen(i, j + 1), p10 = seen(i + 1, j);
              count += !(seen(i, j) || p10 || p01);          // (p00, p10, p01)
              count += !(seen(i + 1, j + 1) || p01 || p10);  // (p11, p01, p10)
            }
        }
        return count;
      },
      [](size_t a, size_t b) { return a + b; });
  return inGrids + tbb::parallel_reduce(
                       tbb::blocked_range<size_t>(0, m.numTriangles()), size_t{0},
                       [&](const tbb::blocked_range<size_t>& range, size_t count) {
                         for (size_t t = range.begin(); t != range.end(); ++t) {
                           bool seen = false;
                           for (int k = 0; k < 3 && !seen; ++k)
                             seen = screen.pointInView(m.positions[m.indices[3 * t + k]]);
                           count += !seen;
                         }
                         return count;
                       },
                       [](size_t a, size_t b) { return a + b; });
}

void countFaces(const LimitSurface& surface, const FaceDicing& faces,
                const std::vector<char>& inView, AdaptiveTessellationStats& stats) {
  for (int f = 0; f < surface.numFaces(); ++f) {
    if (!surface.hasLimitSurface(f)) continue;
    if (!inView[f])
      ++stats.facesCulled;
    else if (faces.needsDicing.empty() || faces.needsDicing[f])
      ++stats.facesDiced;
  }
}

// The mesh of one surface for its chosen rates, and its figures.
void tessellateSurface(SurfaceDicing& d, RateChoice& choice, const ScreenMetric& screen,
                       AdaptiveTessellation& result) {
  AdaptiveTessellationStats& stats = result.stats;
  const AdaptiveSurface& in = *d.input;
  countFaces(*in.surface, in.faces, d.inView, stats);
  stats.facesSplit = choice.facesSplit;
  result.edgeRates = std::move(choice.rates);
  Timer timer;
  try {
    result.mesh =
        d.engine->tessellate(result.edgeRates, in.displacement, &result.grids, choice.splits);
  } catch (const EdgeRateTessellator::NotBilinearGrid&) {
    // A degenerate chart: hits in such a grid need the mesh's triangles, so store them all.
    d.engine->setGridsOnly(false);
    result.mesh =
        d.engine->tessellate(result.edgeRates, in.displacement, &result.grids, choice.splits);
  }
  stats.evaluateSeconds = timer.seconds();
  stats.micropolygons = result.mesh.numMicropolygons();
  stats.offScreenMicropolygons = countOffScreen(result.mesh, result.grids, screen);
  stats.vertices = result.mesh.positions.size();
  if (!result.edgeRates.empty()) {
    const auto [lo, hi] = std::minmax_element(result.edgeRates.begin(), result.edgeRates.end());
    stats.minEdgeRate = *lo;
    stats.maxEdgeRate = *hi;
  }
}

}  // namespace

std::vector<AdaptiveTessellation> tessellateAdaptive(std::span<const AdaptiveSurface> surfaces,
                                                     const ScreenMetric& screen,
                                                     const DicingSettings& settings) {
  for (const AdaptiveSurface& in : surfaces) {
    if (!in.surface) throw Error("adaptive tessellation: a surface is missing");
    validate(*in.surface, settings, in.faces);
  }
  Timer timer;
  std::vector<SurfaceDicing> dicings;
  for (const AdaptiveSurface& in : surfaces)
    dicings.push_back(measureSurface(in, screen, settings));
  FrameChoice frame = chooseRates(dicings, screen, settings);
  const double rateSeconds = timer.seconds();
  std::vector<AdaptiveTessellation> results(surfaces.size());
  for (size_t k = 0; k < surfaces.size(); ++k) {
    AdaptiveTessellation& result = results[k];
    // The shared choice of rates is timed once, with the first surface.
    result.stats.rateSeconds = k == 0 ? rateSeconds : 0.0;
    const size_t count = frame.surfaces[k].count;
    if (std::isfinite(frame.cap.beyond)) {
      result.stats.coarsenedBeyond = frame.cap.beyond;
      result.stats.coarsening = frame.cap.factor(dicings[k].farthest);
      if (result.stats.coarsening > 1.0f)
        result.warning = capWarning(settings, frame, count, dicings[k].farthest);
    }
    tessellateSurface(dicings[k], frame.surfaces[k], screen, result);
  }
  return results;
}

AdaptiveTessellation tessellateAdaptive(const LimitSurface& surface, const ScreenMetric& screen,
                                        const DicingSettings& settings, const FaceDicing& faces,
                                        const VertexDisplacement* displacement) {
  const AdaptiveSurface in{.surface = &surface, .faces = faces, .displacement = displacement};
  return std::move(tessellateAdaptive(std::span(&in, 1), screen, settings)[0]);
}

}  // namespace meso
