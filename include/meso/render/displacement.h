// True displacement of relief levels (Becker & Max 1993 section 2.3, DESIGN.md section 5): how far
// each level is raised at a point, the vertex offsets the adaptive tessellator applies, and which
// faces need micropolygons at all.
#pragma once

#include "meso/appearance/material_tables.h"
#include "meso/appearance/visible_height.h"
#include "meso/geometry/adaptive_tessellation.h"
#include "meso/geometry/limit_surface.h"
#include "meso/geometry/uv_speed.h"
#include "meso/relief/level_frames.h"
#include "meso/render/transition.h"
#include "meso/scene/scene.h"

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace meso {

// How the surface at one point is displaced: disp_i per level (0 for levels left flat) and the
// number of leading levels with disp > 0 (finer levels have shorter wavelengths, hence lower T, so
// the raised levels are always a prefix).
struct LevelDisplacement {
  std::array<float, kMaxReliefLevels> disp{};
  int raised = 0;
};

// The vertex offsets of one material's relief: sum_i disp_i h_i(u, v) N_i, where N_i is the normal
// of the surface after levels 1..i-1 were raised, P_u[i+1] = P_u[i] + disp_i B_u[i] N[i]. In
// ByTransition mode the part of a level drawn flat, 1 - disp_i, lies at the mean height of the
// view's first hits on it (VisibleHeight), so that the silhouettes of flat-drawn relief reach as
// far as the displaced relief's: sum_i (disp_i h_i + (1 - disp_i) E_i[h_hit](theta_V)) N_i.
class ReliefDisplacement : public VertexDisplacement {
 public:
  // lights: those whose terminators count in T (levelTransitions); empty without shadows.
  // surface (may be null): the limit surface that offset() is called on, whose own curvature
  // then bounds the visible height of flat levels at its silhouettes (see crestCurvature).
  // speed (may be null or empty): the surface's UvSpeed, which offset() gives T as its length per
  // unit of u (the shader passes the same), for relief over (u, v).
  ReliefDisplacement(const MaterialRelief& relief, DisplacementMode mode,
                     const TransitionSettings& transition, Vec3 eye, float pixelsPerRadian,
                     std::span<const Light> lights = {}, const LimitSurface* surface = nullptr,
                     SolidSpace solid = {}, const UvSpeed* speed = nullptr);
  // Not copied: visible_ may point into ownVisible_.
  ReliefDisplacement(const ReliefDisplacement&) = delete;
  ReliefDisplacement& operator=(const ReliefDisplacement&) = delete;
  Vec3 offset(int face, Vec2 st, const SurfacePoint& sp) const override;
  float bound() const override { return bound_; }

  // disp per level at a limit-surface point seen from the eye (the vertex rule; the shader
  // recomputes T at its hit in the same way).
  LevelDisplacement levels(const SurfacePoint& sp) const;

 private:
  const MaterialRelief& relief_;
  DisplacementMode mode_;
  TransitionSettings transition_;
  Vec3 eye_;
  float pixelsPerRadian_;
  float bound_ = 0.0f;
  std::vector<Light> lights_;
  SolidSpace solid_;  // the object's, for solid relief (reliefChart)
  const UvSpeed* speed_ = nullptr;
  // Per level in ByTransition mode: the relief's own (MaterialRelief::visibleHeights) or built
  // here. The crest curvature is that of the raised coarser levels plus, given the surface, the
  // limit surface's own; without it a smooth object's silhouette takes the plane's (larger) value.
  std::vector<VisibleHeight> ownVisible_;
  std::span<const VisibleHeight> visible_;
  // Per base face (ByTransition mode with a surface): the limit surface's shape operator at the
  // face's centre, world to world (dN = W dP on the tangent plane, W N = 0), so that the normal
  // curvature along a tangent direction d is d . W d (positive where the surface is convex).
  // Made when a vertex of the face is first displaced (shapeAt): a frame displaces few of a large
  // ground's faces (62 434 of 409 600 on the 640-unit ground of docs/performance.md).
  // Kept in chunks of kShapeChunk faces, each allocated when a face of it first stores a non-zero
  // operator: a flat ground holds none (an array for every face, even untouched, took heap that
  // dicing would have reused: the 640-unit ground's frame peaked 8 MiB higher).
  static constexpr size_t kShapeChunk = 1024;
  struct ShapeChunks {
    std::unique_ptr<std::atomic<Mat3*>[]> chunks;
    size_t count = 0;
    ShapeChunks() = default;
    ShapeChunks(const ShapeChunks&) = delete;
    ShapeChunks& operator=(const ShapeChunks&) = delete;
    ~ShapeChunks();
    // Face f's slot, its chunk allocated if need be (by one thread: the others take that one).
    Mat3& slot(size_t f);
  };
  const LimitSurface* surface_ = nullptr;
  mutable ShapeChunks shape_;  // each face's written once, before its state says so
  std::unique_ptr<std::atomic<uint8_t>[]> shapeState_;  // ShapeState per face
  enum ShapeState : uint8_t { kShapeUnknown, kShapeWriting, kShapeStored, kShapeZero };
  // The face's shape operator, or nothing where it is zero (a flat face), made and kept on first
  // use; a thread that finds another storing it makes its own (the same bits).
  std::optional<Mat3> shapeAt(int face) const;

  // sp and coord: the point as reliefChart gives it.
  Vec3 flatLevelsOffset(const LevelTransitions& t, const SurfacePoint& sp, const ReliefCoord& coord,
                        int face) const;
  // The sum of the raised levels' second derivatives at one point, kept between the flat levels
  // of that point: level i needs levels 0 .. min(i, raised) - 1, level i + 1 those and more.
  struct CrestSum {
    bool started = false, usable = false;
    Vec2 w{0.0f};  // the uv direction of one world unit across the view
    float second = 0.0f;
    int done = 0;  // levels summed
    bool shapeKnown = false;
    std::optional<Mat3> shape;  // shapeAt(face)
  };
  float crestCurvature(const LevelTransitions& t, int level, const SurfacePoint& sp,
                       const ReliefCoord& coord, Vec3 V, int face, CrestSum& sum) const;
};

// sum_i amplitude_i * max |h_i|: no vertex moves further (world units).
float displacementBound(const MaterialRelief& relief);

// Relief samples per texel of a height image: its shortest wavelength is two texels, so
// render.relief_samples edges per wavelength are half as many per texel (2 at the default 4),
// unless render.texel_samples says otherwise. One edge per texel is not enough: where a face's
// vertices fall on texel corners, each takes the mean of four texels and the image's Nyquist
// band vanishes from the geometry (a 1/f photograph-like map on a plane: -3.1% at one edge per
// texel, +0.2% at two, against eight; docs/validation.md).
inline constexpr float kReliefSamplesPerTexel = 2.0f;

// The hybrid's floor on a coupled height image (displacement.cpp) stops at one edge per texel,
// unless render.texel_samples says otherwise: on scenes/bricks.toml two per texel bring its
// worst depth band from -0.67% to -0.41% of the converged reference for 3.6 times the
// micropolygons (68 M against 18.8 M, more than full displacement's 24 M at one per texel).
inline constexpr float kHybridFloorEdgesPerTexel = 1.0f;

// How finely full displacement samples relief where it is below a pixel.
struct ReliefSampling {
  // render.relief_samples: at least this many edges per shortest wavelength where sub-pixel relief
  // can mask itself (the texel floor; full displacement, and the hybrid where it raises a height
  // image with detail below its level's wavelength); 0 = pixel dicing only.
  float perWavelength = 0.0f;
  // render.texel_samples: at most this many edges per texel of a height image (the texel cap);
  // 0 = perWavelength / kReliefSamplesPerTexel, at least 1. Above 1 each texel's bilinear patch is
  // diced, which still curves and casts shadows below the texel (a converged reference needs 2 to
  // 8 on sharp-edged images: docs/validation.md).
  float perTexel = 0.0f;
  float texelEdges() const {
    return perTexel > 0.0f ? perTexel : std::max(1.0f, perWavelength / kReliefSamplesPerTexel);
  }
  // Where the hybrid's floor stops on a height image: render.texel_samples, or one edge per texel.
  float hybridFloorTexelEdges() const {
    return perTexel > 0.0f ? perTexel : kHybridFloorEdgesPerTexel;
  }
};

// Samples of a level per unit of u: the spacing below which dicing stops (the texel cap). A height
// table has max(W, H) * S texels per unit of u, times sampling.texelEdges(); procedural noise is
// sampled max(8, 2 perWavelength) times per shortest wavelength: 8 resolve its silhouettes and
// self-occlusion (the shading normal is its Blinn normal; on the terrain 8 instead of 16 changed
// no depth band by more than 0.05%), and twice the relief samples keeps the cap above the floor,
// so a reference that doubles them is refined, not capped.
float samplesPerU(const ReliefLevel& level, const ReliefSampling& sampling);

// Root of the summed mean squares of every level's height derivative along u or v (the larger),
// per unit of u, from 1024 fixed points per level: the relief's rms slope on a unit-speed surface.
float reliefSlopeRmsPerU(const MaterialRelief& relief);

// Per face: whether some level can be raised there in this view (always, in Full mode; in
// ByTransition mode, when the coarsest level's nu at the face's nearest point exceeds
// D + e3 * eps, the least nu for which T can exceed e3 at a grazing angle), and the texel cap
// (the edge rate at which micropolygons reach the sample spacing of the finest level that can be
// raised on the face: every level in Full mode, in ByTransition mode those whose nu can exceed
// D + e3 * eps there; finer levels are drawn flat, so dicing below their texels buys nothing).
// In Full mode also the texel floor: at least sampling.perWavelength micropolygon edges per
// shortest wavelength of the finest level (at most its texel cap), so that relief smaller than a
// pixel is still resolved by the geometry (0: pixel dicing only), on faces where the relief can
// mask itself: where the most grazing view of the face's corners and centre has cot(theta_V) below
// 3 times the relief's world rms slope. Elsewhere under-resolved relief already shows its normals
// with their true distribution, and the floor would only cost micropolygons. In ByTransition mode
// the same floor on the faces that raise the finest level when it is a height image whose texels
// carry detail finer than its wavelength (highestFrequency() * scale above freqPerU): pixel dicing
// resolves its wavelength where it is raised, not its texel-scale relief.
// In ByTransition mode also the raise distance: the distance from the eye beyond which that nu
// (with the face's largest length per u) falls to D + e3 * eps, so that the parts of a face
// beyond it are diced coarsely (FaceDicing::raiseDistance).
// For solid relief (`solid` active) lengths along the surface are measured in units of solid space
// (world edge lengths over SolidSpace::lengthPerUnit) instead of in (u, v).
// speed (may be null or empty): the surface's UvSpeed, whose corners bound the length per u T
// reads on each face.
// view (may be null): the frame's. A face that it does not see (faceInView, grown by
// displacementBound(relief), the bound of the relief's ReliefDisplacement) keeps the defaults
// unevaluated: adaptive tessellation reads no entry of a face it culls, so the frame's geometry is
// the same, and a ground of many faces mostly out of view does not sample each of them.
FaceDicing faceDicing(const LimitSurface& surface, const MaterialRelief& relief,
                      DisplacementMode mode, const TransitionSettings& transition, Vec3 eye,
                      float pixelsPerRadian, const ReliefSampling& sampling = {},
                      const SolidSpace& solid = {}, const UvSpeed* speed = nullptr,
                      const ScreenMetric* view = nullptr);

}  // namespace meso
