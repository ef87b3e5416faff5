// Becker & Max 1993, section 2.3 and eq. (10); DESIGN.md sections 3 and 5.
#include "meso/render/displacement.h"

#include "meso/relief/level_frames.h"
#include "meso/render/transition.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace meso {

float displacementBound(const MaterialRelief& relief) {
  double sum = 0.0;
  for (const ReliefLevel& level : relief.levels)
    sum += std::abs(static_cast<double>(level.amplitude)) *
           (static_cast<double>(level.source->maxAbsHeight()) + std::abs(level.midlevel));
  return std::isfinite(sum) ? static_cast<float>(sum) : std::numeric_limits<float>::infinity();
}

float samplesPerU(const ReliefLevel& level, const ReliefSampling& sampling) {
  if (const int texels = level.source->texelsPerSide(); texels > 0)
    return static_cast<float>(texels) * level.scale * sampling.texelEdges();
  return std::max(8.0f, 2.0f * sampling.perWavelength) * level.freqPerU;
}

namespace {

// The limit surface's shape operator at the centre of base face f (see ReliefDisplacement::
// shape_), from one-sided differences over a hundredth of the face; zero where the surface is
// degenerate there (no usable tangents or normals), which leaves the plane's visible height.
Mat3 shapeOperator(const LimitSurface& surface, int face) {
  if (!surface.hasLimitSurface(face)) return Mat3(0.0f);
  const int corners = surface.faceSize(face);
  Vec2 centre(0.0f);
  for (int k = 0; k < corners; ++k) centre += surface.cornerSt(face, k);
  centre /= static_cast<float>(corners);
  constexpr float kStep = 0.01f;
  const SurfacePoint c = surface.evaluate(face, centre);
  const SurfacePoint s = surface.evaluate(face, centre + Vec2(kStep, 0.0f));
  const SurfacePoint t = surface.evaluate(face, centre + Vec2(0.0f, kStep));
  // W [P_s P_t N] = [N_s N_t 0].
  const Mat3 dP((s.P - c.P) / kStep, (t.P - c.P) / kStep, c.N);
  const Mat3 dN((s.N - c.N) / kStep, (t.N - c.N) / kStep, Vec3(0.0f));
  const float det = glm::determinant(dP);
  if (!(std::abs(det) > 1e-12f) || !std::isfinite(det)) return Mat3(0.0f);
  const Mat3 W = dN * glm::inverse(dP);
  for (int k = 0; k < 3; ++k)
    if (!isFinite(W[k])) return Mat3(0.0f);
  return W;
}

}  // namespace

ReliefDisplacement::ReliefDisplacement(const MaterialRelief& relief, DisplacementMode mode,
                                       const TransitionSettings& transition, Vec3 eye,
                                       float pixelsPerRadian, std::span<const Light> lights,
                                       const LimitSurface* surface, SolidSpace solid,
                                       const UvSpeed* speed)
    : relief_(relief),
      mode_(mode),
      transition_(transition),
      eye_(eye),
      pixelsPerRadian_(pixelsPerRadian),
      bound_(displacementBound(relief)),
      lights_(lights.begin(), lights.end()),
      solid_(solid),
      speed_(speed && !speed->empty() && !solid.active ? speed : nullptr) {
  if (mode != DisplacementMode::ByTransition) return;
  if (surface && surface->numFaces() > 0) {
    surface_ = surface;
    const size_t faces = static_cast<size_t>(surface->numFaces());
    shape_.count = (faces + kShapeChunk - 1) / kShapeChunk;
    shape_.chunks = std::make_unique<std::atomic<Mat3*>[]>(shape_.count);
    shapeState_ = std::make_unique<std::atomic<uint8_t>[]>(faces);
  }
  if (relief.visibleHeights.size() == relief.levels.size()) {
    visible_ = relief.visibleHeights;
    return;
  }
  for (const ReliefLevel& level : relief.levels) ownVisible_.emplace_back(level);
  visible_ = ownVisible_;
}

ReliefDisplacement::ShapeChunks::~ShapeChunks() {
  for (size_t c = 0; c < count; ++c) delete[] chunks[c].load(std::memory_order_relaxed);
}

Mat3& ReliefDisplacement::ShapeChunks::slot(size_t f) {
  std::atomic<Mat3*>& chunk = chunks[f / kShapeChunk];
  Mat3* mine = chunk.load(std::memory_order_acquire);
  if (!mine) {
    Mat3* made = new Mat3[kShapeChunk];
    if (chunk.compare_exchange_strong(mine, made, std::memory_order_acq_rel))
      mine = made;
    else
      delete[] made;  // another thread's came first: `mine` is now that one
  }
  return mine[f % kShapeChunk];
}

std::optional<Mat3> ReliefDisplacement::shapeAt(int face) const {
  if (!surface_ || face < 0 || face >= surface_->numFaces()) return std::nullopt;
  std::atomic<uint8_t>& state = shapeState_[static_cast<size_t>(face)];
  switch (state.load(std::memory_order_acquire)) {
    case kShapeStored:
      return shape_.chunks[static_cast<size_t>(face) / kShapeChunk].load(
          std::memory_order_relaxed)[static_cast<size_t>(face) % kShapeChunk];
    case kShapeZero:
      return std::nullopt;
    default:
      break;
  }
  const Mat3 W = shapeOperator(*surface_, face);
  const bool zero = W == Mat3(0.0f);
  uint8_t expected = kShapeUnknown;
  if (state.compare_exchange_strong(expected, kShapeWriting, std::memory_order_acquire)) {
    if (!zero) shape_.slot(static_cast<size_t>(face)) = W;
    state.store(zero ? kShapeZero : kShapeStored, std::memory_order_release);
  }
  return zero ? std::nullopt : std::optional<Mat3>(W);
}

LevelDisplacement ReliefDisplacement::levels(const SurfacePoint& limit) const {
  ReliefCoord coord;
  const SurfacePoint sp = reliefChart(limit, solid_, coord);
  const LevelTransitions t =
      levelTransitions(relief_, sp, coord, eye_, pixelsPerRadian_, transition_, mode_, lights_);
  LevelDisplacement out;
  out.disp = t.disp;
  out.raised = t.raised;
  return out;
}

// The convex curvature (1 / world units) along the view's tangent direction of the levels raised
// below `level` and of the limit surface itself (base face `face`, when the surface was given): a
// silhouette on a crest of radius R is grazed over a path about sqrt(2 R h) long, not over the
// unbounded plane Smith's model assumes. `sum` carries the levels already
// summed at this point to the next flat level (the same sum in the same order, so the same bits).
float ReliefDisplacement::crestCurvature(const LevelTransitions& t, int level,
                                         const SurfacePoint& sp, const ReliefCoord& coord, Vec3 V,
                                         int face, CrestSum& sum) const {
  const int below = std::min(level, t.raised);
  // The limit surface's own curvature (none on a flat face) is looked up once per point.
  if (!sum.shapeKnown) {
    sum.shape = shapeAt(face);
    sum.shapeKnown = true;
  }
  if (below == 0 && !sum.shape) return 0.0f;
  if (!sum.started) {
    sum.started = true;
    const Vec3 N = t.frames[0].N;
    const Vec3 across = V - glm::dot(V, N) * N;
    const float length = glm::length(across);
    if (!(length > 1e-6f)) return 0.0f;
    // The uv direction of one world unit along `across`: solve [P_u P_v] w = across / length.
    const Vec3 dir = across / length;
    // The limit surface's own second derivative along dir: minus its normal curvature there.
    if (sum.shape) {
      const float kappa = glm::dot(dir, *sum.shape * dir);
      if (std::isfinite(kappa)) sum.second = -kappa;
    }
    const float a = glm::dot(sp.Pu, sp.Pu), b = glm::dot(sp.Pu, sp.Pv), c = glm::dot(sp.Pv, sp.Pv);
    const float det = a * c - b * b;
    if (!(std::abs(det) > 0.0f)) return std::max(-sum.second, 0.0f);
    const float ru = glm::dot(sp.Pu, dir), rv = glm::dot(sp.Pv, dir);
    sum.w = Vec2((c * ru - b * rv) / det, (a * rv - b * ru) / det);
    sum.usable = true;
  }
  if (!sum.usable) return std::max(-sum.second, 0.0f);
  const Vec2 w = sum.w;
  // d2h/ds2 of the raised levels, s world length along `across`.
  for (; sum.done < below; ++sum.done) {
    const ReliefLevel& coarse = relief_.levels[sum.done];
    if (const std::optional<float> d2 = coarse.secondDerivative(coord, w)) {
      sum.second += t.disp[sum.done] * *d2;
      continue;
    }
    const float step = coarse.wavelength() / (16.0f * std::max(glm::length(w), 1e-12f));
    const Vec2 slope =
        coarse.derivatives(coord.offset(step * w)) - coarse.derivatives(coord.offset(-step * w));
    sum.second += t.disp[sum.done] * glm::dot(slope, w) / (2.0f * step);
  }
  return std::isfinite(sum.second) ? std::max(-sum.second, 0.0f) : 0.0f;
}

// (1 - disp_i) E_i[h_hit] N_i over the levels drawn flat (visible_height.h).
Vec3 ReliefDisplacement::flatLevelsOffset(const LevelTransitions& t, const SurfacePoint& sp,
                                          const ReliefCoord& coord, int face) const {
  const Vec3 toEye = eye_ - sp.P;
  const float distance = glm::length(toEye);
  const Vec3 V = distance > 0.0f && std::isfinite(distance) ? toEye / distance : sp.N;
  const float lengthPerU = std::min(glm::length(sp.Pu), glm::length(sp.Pv));
  Vec3 offset(0.0f);
  CrestSum crest;
  for (int i = 0; i < t.count; ++i) {
    if (!(t.disp[i] < 1.0f)) continue;
    // An image band drawn with its finer bands as one level: their sum's visible height.
    const ReliefLevel& level = relief_.levels[i];
    const int next = level.partialSum ? static_cast<int>(level.partialSumEnd) : i + 1;
    const auto advance = [&] { i = std::max(i, next - 1); };
    const float cosTheta = glm::dot(t.frames[i].N, V);
    if (!visible_[i].grazing(cosTheta, lengthPerU)) {
      advance();
      continue;
    }
    const float curvature = crestCurvature(t, i, sp, coord, V, face, crest);
    offset +=
        ((1.0f - t.disp[i]) * visible_[i].at(cosTheta, lengthPerU, curvature)) * t.frames[i].N;
    advance();
  }
  return offset;
}

Vec3 ReliefDisplacement::offset(int face, Vec2 st, const SurfacePoint& limit) const {
  ReliefCoord coord;
  const SurfacePoint sp = reliefChart(limit, solid_, coord);
  const LevelTransitions t =
      levelTransitions(relief_, sp, coord, eye_, pixelsPerRadian_, transition_, mode_, lights_,
                       TransitionsFor::Offsets, speed_ ? speed_->at(face, st) : 0.0f);
  Vec3 offset(0.0f);
  for (int i = 0; i < t.raised; ++i) offset += (t.disp[i] * t.H[i]) * t.frames[i].N;
  if (!visible_.empty()) offset += flatLevelsOffset(t, sp, coord, face);
  // A non-finite height or frame must not put a vertex at infinity: leave it on the limit surface.
  return std::isfinite(offset.x) && std::isfinite(offset.y) && std::isfinite(offset.z) ? offset
                                                                                       : Vec3(0.0f);
}

namespace {

// Masking decides whether sub-pixel relief must be resolved: where no facet of the relief hides
// another one at this view, under-resolved micropolygons shaded with the relief's own normals see
// its normals with their true distribution f. For Gaussian slopes of rms sigma per direction,
// Smith's Lambda(a), a = cot(theta_V) / (sqrt(2) sigma), is below 2e-4 for cot(theta_V) >= 3 sigma.
constexpr float kMaskingSlopes = 3.0f;

}  // namespace

float reliefSlopeRmsPerU(const MaterialRelief& relief) {
  double sum = 0.0;
  for (const ReliefLevel& level : relief.levels) sum += levelSlopeMeanSquarePerU(level);
  const float rms = static_cast<float>(std::sqrt(sum));
  return std::isfinite(rms) ? rms : std::numeric_limits<float>::infinity();
}

namespace {

// What faceDicing needs to know of one face, from its corners and centre.
struct FaceSample {
  Vec3 lo, hi;              // box of the face's limit patch
  float uvEdge = 0.0f;      // longest edge in uv
  float lengthPerU = 0.0f;  // the largest max(|P_u|, |P_v|) of the points
  float shortestPerU = std::numeric_limits<float>::infinity();  // the smallest
  float leastCot = std::numeric_limits<float>::infinity();      // most grazing view: cot(theta_V)
};

bool sampleFace(const LimitSurface& surface, int face, Vec3 eye, const SolidSpace& solid,
                FaceSample& s) {
  if (!surface.faceBox(face, s.lo, s.hi)) return false;
  const auto seen = [&](const SurfacePoint& sp) {
    const float lu = solid.active ? solid.lengthPerUnit : glm::length(sp.Pu);
    const float lv = solid.active ? solid.lengthPerUnit : glm::length(sp.Pv);
    s.shortestPerU = std::min(s.shortestPerU, std::min(lu, lv));
    s.lengthPerU = std::max(s.lengthPerU, std::max(lu, lv));
    const Vec3 toEye = eye - sp.P;
    const float along = std::abs(glm::dot(sp.N, toEye)),
                across = glm::length(glm::cross(sp.N, toEye));
    s.leastCot = std::min(s.leastCot, across > 0.0f ? along / across : s.shortestPerU);
  };
  const int corners = surface.faceSize(face);
  Vec2 centre(0.0f);
  SurfacePoint previous = surface.evaluate(face, surface.cornerSt(face, corners - 1));
  for (int k = 0; k < corners; ++k) {
    const Vec2 st = surface.cornerSt(face, k);
    const SurfacePoint sp = surface.evaluate(face, st);
    centre += st / static_cast<float>(corners);
    // Solid relief: the edge's world length in units of solid space.
    s.uvEdge =
        std::max(s.uvEdge, solid.active ? glm::length(sp.P - previous.P) / solid.lengthPerUnit
                                        : glm::length(sp.uv - previous.uv));
    seen(sp);
    previous = sp;
  }
  seen(surface.evaluate(face, centre));
  return true;
}

// ceil(uvEdge * perU) clamped to [1, limit]; 0 (none) where perU is not positive or the product
// not finite.
int edgeRateFor(float uvEdge, float perU, float limit) {
  if (!(perU > 0.0f) || !std::isfinite(uvEdge * perU)) return 0;
  return static_cast<int>(std::clamp(std::ceil(uvEdge * perU), 1.0f, limit));
}

}  // namespace

FaceDicing faceDicing(const LimitSurface& surface, const MaterialRelief& relief,
                      DisplacementMode mode, const TransitionSettings& transition, Vec3 eye,
                      float pixelsPerRadian, const ReliefSampling& sampling,
                      const SolidSpace& solid, const UvSpeed* speed, const ScreenMetric* view) {
  const int n = surface.numFaces();
  if (speed && (speed->empty() || solid.active)) speed = nullptr;
  FaceDicing out;
  out.needsDicing.assign(static_cast<size_t>(n), 0);
  out.texelCap.assign(static_cast<size_t>(n), 0);
  out.texelFloor.assign(static_cast<size_t>(n), 0);
  if (mode == DisplacementMode::ByTransition)
    out.raiseDistance.assign(static_cast<size_t>(n), std::numeric_limits<float>::infinity());
  if (relief.levels.empty()) return out;
  const float bound = displacementBound(relief);
  // The least nu that T can raise a level at.
  const auto threshold = [&](const ReliefLevel& level) {
    return levelD(level, transition) + transition.e3 * transition.eps;
  };
  // The floor resolves the relief's own finest wavelength: an image level whose T follows a
  // coarser band (coupled bands, scene/relief_bands.h) still has the image's finest detail.
  const ReliefLevel& finestLevel = relief.levels.back();
  const float floorFreqPerU =
      finestLevel.source->texelsPerSide() > 0
          ? std::max(finestLevel.freqPerU,
                     finestLevel.source->highestFrequency() * finestLevel.scale)
          : finestLevel.freqPerU;
  // The hybrid floors a height image where it raises a band of it, since dicing by pixels does not
  // resolve a texel grid's relief: a coupled level (its texels carry detail finer than its
  // measured wavelength: sharp edges, per-texel noise) is raised where its texels are below a
  // pixel, and its texel-scale relief masks itself at grazing views; a band of a split image is
  // raised where its measured wavelength spans D pixels or more, but its spectrum reaches above
  // that (a band's edges are half an octave wide), and the finest band's wavelength is two texels:
  // one edge per pixel is then about one per texel, whose vertices can fall on texel corners, each
  // the mean of four texels, and the band vanishes from the geometry (kReliefSamplesPerTexel). The
  // coupled floor stops at the hybrid's own texel limit (kHybridFloorEdgesPerTexel), a band's at
  // the texel cap.
  const bool imageFloor =
      mode == DisplacementMode::ByTransition &&
      std::any_of(relief.levels.begin(), relief.levels.end(),
                  [](const ReliefLevel& l) { return l.source->texelsPerSide() > 0; });
  const float hybridFloorCapPerU = floorFreqPerU > finestLevel.freqPerU
                                       ? static_cast<float>(finestLevel.source->texelsPerSide()) *
                                             finestLevel.scale * sampling.hybridFloorTexelEdges()
                                       : std::numeric_limits<float>::infinity();
  const float slopePerU =
      (mode == DisplacementMode::Full || imageFloor) && sampling.perWavelength > 0.0f
          ? reliefSlopeRmsPerU(relief)
          : 0.0f;
  // At least perWavelength edges per finest wavelength where the relief can mask itself (the most
  // grazing view of the face against its world rms slope), up to the texel cap.
  const auto floorFace = [&](int face, const FaceSample& s, float capPerU, float freqPerU) {
    const float slope =
        s.shortestPerU > 0.0f ? slopePerU / s.shortestPerU : std::numeric_limits<float>::infinity();
    if (!(s.leastCot >= kMaskingSlopes * slope))
      out.texelFloor[face] =
          edgeRateFor(s.uvEdge, std::min(sampling.perWavelength * freqPerU, capPerU),
                      out.texelCap[face] > 0 ? static_cast<float>(out.texelCap[face]) : 32767.0f);
  };
  const float viewGrow = std::max(bound, 0.0f);  // as adaptive tessellation grows its test
  tbb::parallel_for(0, n, [&](int face) {
    if (view && !faceInView(surface, *view, face, viewGrow)) return;
    FaceSample s;
    if (!sampleFace(surface, face, eye, solid, s)) return;
    // T reads the mesh's UvSpeed, interpolated from the face's corners: none exceeds their largest.
    if (speed) s.lengthPerU = std::max(s.lengthPerU, speed->faceMax(face));
    if (mode == DisplacementMode::Full) {
      const float capPerU = samplesPerU(finestLevel, sampling);
      out.texelCap[face] = edgeRateFor(s.uvEdge, capPerU, 32767.0f);
      floorFace(face, s, capPerU, floorFreqPerU);  // a non-finite slope (a degenerate face) masks
      out.needsDicing[face] = 1;
      return;
    }
    // The largest nu of a level on the face: seen from the nearest point of the face's box grown
    // by the bound; lengthPerU is padded by 25% because it was sampled at five points only.
    const Vec3 grow(std::isfinite(bound) ? bound : 0.0f);
    const float distance = std::isfinite(bound) ? boxDistance(eye, s.lo - grow, s.hi + grow) : 0.0f;
    const auto maxNu = [&](const ReliefLevel& level) {
      return distance > 0.0f
                 ? level.wavelength() * 1.25f * s.lengthPerU * pixelsPerRadian / distance
                 : std::numeric_limits<float>::infinity();
    };
    const ReliefLevel& coarsest = relief.levels.front();
    out.needsDicing[face] = !(maxNu(coarsest) <= threshold(coarsest));
    if (!out.needsDicing[face]) return;
    // maxNu falls as 1 / distance: no part of the face farther than this from the eye raises its
    // coarsest level (the tessellator dices such parts coarsely).
    const float raise =
        coarsest.wavelength() * 1.25f * s.lengthPerU * pixelsPerRadian / threshold(coarsest);
    if (threshold(coarsest) > 0.0f && raise >= 0.0f) out.raiseDistance[face] = raise;
    // Texels of the finest level that can be raised here: a finer one is drawn flat (BRDF or
    // redistribution) on this face, so dicing below its texels would buy nothing.
    for (size_t i = relief.levels.size(); i-- > 0;)
      if (!(maxNu(relief.levels[i]) <= threshold(relief.levels[i])) || i == 0) {
        const float capPerU = samplesPerU(relief.levels[i], sampling);
        out.texelCap[face] = edgeRateFor(s.uvEdge, capPerU, 32767.0f);
        const ReliefLevel& level = relief.levels[i];
        if (imageFloor && level.source->texelsPerSide() > 0 &&
            !(maxNu(level) <= threshold(level))) {
          if (i + 1 == relief.levels.size())
            floorFace(face, s, std::min(capPerU, hybridFloorCapPerU), floorFreqPerU);
          else
            floorFace(face, s, capPerU, level.freqPerU);
        }
        break;
      }
  });
  return out;
}

}  // namespace meso
