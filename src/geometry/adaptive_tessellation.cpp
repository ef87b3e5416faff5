// View-dependent dicing of a limit surface into displaced micropolygons (Becker & Max 1993 section
// 2.3: vertices displaced along the normal; shared/DESIGN.md section 5: edges at most dicing_rate
// pixels where a level may be displaced, elsewhere just fine enough to follow the limit surface,
// rates shared between neighbouring patches).
#include "meso/geometry/adaptive_tessellation.h"

#include "cap_coarsening.h"
#include "face_split.h"
#include "limit_surface_impl.h"
#include "edge_measure.h"
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

bool mayShadowView(const Vec3& lo, const Vec3& hi, const ScreenMetric& screen,
                   const DicingSettings::ShadowCasters& casters) {
  const Vec3 &slo = casters.sceneLo, &shi = casters.sceneHi;
  // The part of a swept box inside the scene's box, where the points it may shadow lie.
  const auto sweptInView = [&](const Vec3& a, const Vec3& b) {
    const Vec3 l0 = glm::max(a, slo), h0 = glm::min(b, shi);
    return l0.x <= h0.x && l0.y <= h0.y && l0.z <= h0.z &&
           screen.boxInView(l0, h0, 2.0f * screen.nearDistance);  // points nearer than its near
                                                                  // plane are seen too
  };
  for (const Vec3& l : casters.directions) {
    // The points this box may shadow are x - t l (x in the box, t >= 0) inside the scene's box:
    // per axis, x - t l overlaps [slo, shi] for t l in [lo - shi, hi - slo].
    float t0 = 0.0f, t1 = std::numeric_limits<float>::infinity();
    for (int a = 0; a < 3; ++a) {
      const float below = lo[a] - shi[a], above = hi[a] - slo[a];
      if (l[a] > 0.0f) {
        t0 = std::max(t0, below / l[a]);
        t1 = std::min(t1, above / l[a]);
      } else if (l[a] < 0.0f) {
        t0 = std::max(t0, above / l[a]);
        t1 = std::min(t1, below / l[a]);
      } else if (below > 0.0f || above < 0.0f) {
        t1 = -1.0f;
      }
    }
    if (!(t0 <= t1)) {
      if (std::isnan(t0) || std::isnan(t1)) return true;
      continue;
    }
    if (!std::isfinite(t1)) return true;
    if (sweptInView(glm::min(lo - t0 * l, lo - t1 * l), glm::max(hi - t0 * l, hi - t1 * l)))
      return true;
  }
  for (const Vec3& p : casters.points) {
    if (glm::all(glm::greaterThanEqual(p, lo)) && glm::all(glm::lessThanEqual(p, hi))) return true;
    // The points it may shadow are p + s (x - p), s >= 1, inside the scene's box: within the hull
    // of the box's corners seen from p at s = 1 and at the largest s where a corner's ray from p
    // leaves the scene's box.
    float far = 1.0f;
    for (int c = 0; c < 8; ++c) {
      const Vec3 d = Vec3(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z) - p;
      float exit = std::numeric_limits<float>::infinity();
      for (int a = 0; a < 3; ++a)
        if (d[a] != 0.0f)
          exit = std::min(exit, std::max((slo[a] - p[a]) / d[a], (shi[a] - p[a]) / d[a]));
      far = std::max(far, exit);
    }
    if (!std::isfinite(far)) return true;
    Vec3 swept0 = lo, swept1 = hi;
    for (int c = 0; c < 8; ++c) {
      const Vec3 d = Vec3(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z) - p;
      swept0 = glm::min(swept0, p + far * d);
      swept1 = glm::max(swept1, p + far * d);
    }
    if (sweptInView(swept0, swept1)) return true;
  }
  return false;
}

namespace {

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
  std::vector<char> keep;  // empty: every face
  if (settings.shadowCasters)
    keep = facesKept(*in.surface, screen, bound, d.inView, *settings.shadowCasters);
  d.engine = std::make_unique<EdgeRateTessellator>(*in.surface, keep.empty() ? nullptr : &keep);
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

// Triangles none of whose corners is in view: the mesh's, and those only its grids hold. Each point
// is tested once (a grid's point is a corner of up to six triangles).
size_t countOffScreen(const TessellatedMesh& m, const std::vector<TriangleGrid>& grids,
                      const ScreenMetric& screen) {
  std::vector<uint8_t> inView(m.positions.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, inView.size(), 4096),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t i = range.begin(); i != range.end(); ++i)
                        inView[i] = screen.pointInView(m.positions[i]);
                    });
  const size_t inGrids = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, grids.size()), size_t{0},
      [&](const tbb::blocked_range<size_t>& range, size_t count) {
        for (size_t k = range.begin(); k != range.end(); ++k) {
          const TriangleGrid& g = grids[k];
          if (g.firstTriangle != TriangleGrid::kNotInMesh) continue;
          const auto seen = [&](int i, int j) {
            return inView[g.firstVertex + size_t(j) * g.width + i] != 0;
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
                           const uint32_t* c = &m.indices[3 * t];
                           count += !(inView[c[0]] || inView[c[1]] || inView[c[2]]);
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
  // The edges' measures and the split plan are spent once the rates are chosen: they go before the
  // mesh is made, which is the peak of a large mesh's frame.
  std::vector<EdgeMeasure>().swap(d.measures);
  d.plan = SplitPlan{};
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
