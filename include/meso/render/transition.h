// Becker & Max 1993, eq. (10) and section 4: the transition parameter T(d, theta_V), the weights
// of the renderers it selects (DESIGN.md section 3) and what T asks of every level at a point.
#pragma once

#include "meso/appearance/material_tables.h"
#include "meso/geometry/limit_surface.h"
#include "meso/relief/level_frames.h"
#include "meso/scene/scene.h"

#include <algorithm>
#include <array>
#include <span>
#include <string>

namespace meso {

// Throws meso::Error naming `where` (e.g. "render.thresholds") unless e1 < e2 < 0 < e3 < e4, D >=
// 0, eps >= 0 and all are finite.
void validateTransitionSettings(const TransitionSettings& s, const char* where);

// T_i = (nu_i - D) / (cos(theta_V) + eps) with nu_i = lambda_i * p / d the number of pixels the
// level's shortest wavelength spans at distance d (p: pixels per radian). cosThetaV is clamped to
// [0, 1]; with eps = 0 at cos theta_V = 0 the result is clamped to +-1e6 instead of dividing by
// zero.
// Inline (with ramp and transitionWeights): the pixel loop evaluates them for every level of every
// sample.
inline float transitionParameter(float wavelength, float pixelsPerRadian, float distance,
                                 float cosThetaV, const TransitionSettings& s) {
  constexpr float kLimit = 1e6f;
  // A camera touching the surface sees the wavelength over infinitely many pixels: saturate.
  const float nu = distance > 0.0f ? wavelength * pixelsPerRadian / distance : kLimit;
  const float denom = std::clamp(cosThetaV, 0.0f, 1.0f) + s.eps;
  const float num = std::min(nu, kLimit) - s.D;
  if (denom <= 0.0f) return num > 0.0f ? kLimit : (num < 0.0f ? -kLimit : 0.0f);
  return std::clamp(num / denom, -kLimit, kLimit);
}

// T of a level whose octaves span wavelengths `shortest` to `longest` (longest >= shortest): as
// above with the shortest where that is positive (nu_short > D: how far to raise the geometry, the
// paper's T), else min(0, T of the longest). So T is 0 (redistribution) while the shortest
// wavelength spans fewer than D pixels and the longest more, and the BRDF table takes over only
// where the longest spans fewer than D: a table keeps a pixel's mean, and while a coarse octave
// still spans pixels the pixel filter keeps its pixel-to-pixel variation, which bump normals
// redistributed per sample keep and a table does not (docs/terrain.md, "Local contrast at
// 320x180"). Continuous and non-decreasing in nu; equal to the form above for one octave.
inline float transitionParameter(float shortest, float longest, float pixelsPerRadian,
                                 float distance, float cosThetaV, const TransitionSettings& s) {
  const float t = transitionParameter(shortest, pixelsPerRadian, distance, cosThetaV, s);
  if (t >= 0.0f || !(longest > shortest)) return t;
  return std::min(0.0f, transitionParameter(longest, pixelsPerRadian, distance, cosThetaV, s));
}

// The C1 ramp used for every blend: 0 at a, 1 at b, smoothstep between (derivative 0 at both ends,
// so weights are continuous in T with a continuous slope).
inline float ramp(float t, float a, float b) {
  const float x = std::clamp((t - a) / (b - a), 0.0f, 1.0f);
  return x * x * (3.0f - 2.0f * x);
}

// What T asks of one level. Weights sum to 1 between brdf and the bump-based renderers; disp is the
// fraction of the relief height raised as geometry (0: flat, 1: fully displaced).
struct TransitionWeights {
  float brdf = 0.0f;            // weight of the BRDF table intensity (T < e2)
  float redistribution = 0.0f;  // weight of redistribution / partial / full displacement (1 - brdf)
  float disp = 0.0f;            // ramp(T; e3, e4)
};

inline TransitionWeights transitionWeights(float T, const TransitionSettings& s) {
  TransitionWeights w;
  w.redistribution = ramp(T, s.e1, s.e2);
  w.brdf = 1.0f - w.redistribution;
  w.disp = ramp(T, s.e3, s.e4);
  return w;
}

// Full: every level is raised completely (the reference renderer, --algorithm displacement).
// ByTransition: level i is raised by disp_i = ramp(T_i; e3, e4) (auto mode); 0 below e3.
enum class DisplacementMode { Full, ByTransition };

// A level of a height image takes D times this (render.D 2 gives 1): the relief users bring as
// images carries its contrast over every octave up to the texels' Nyquist limit, and at D = 2 a
// band whose shortest wavelength spans 1 to 2 pixels goes to the tables, which keep its mean but
// not its texture at grazing views. Measured against the converged reference (docs/validation.md,
// "A photograph-like map and a sculpted map"): the far rows of a 1/f map on a plane keep 0.810 of
// the reference's local contrast at D = 2 and 0.942 at D = 1, a sculpted map 0.907 and 0.994, the
// floor of scenes/bricks.toml 0.862 and 0.978, and the 1/f map on a UV sphere is -1.50% and -0.33%
// in its lowest rows (shadows near the terminator traced, not tabulated). Procedural relief keeps
// D.
inline constexpr float kHeightImageDScale = 0.5f;

// D for one level: render.D, times kHeightImageDScale for a level of a height image.
float levelD(const ReliefLevel& level, const TransitionSettings& settings);

// The transition parameter of a level at a point: T = (nu - D) / (|cos theta_V| + eps) with
// nu = wavelength * lengthPerU * pixelsPerRadian / distance (DESIGN.md section 3) and D = levelD.
// lengthPerU is the world length of one unit of u at the point along the direction where it is
// longest, max(|P_u|, |P_v|) of the limit surface (levelTransitions): where the uv is compressed
// along one direction (a UV sphere towards its poles, a stretched chart), the relief's detail along
// the other is as large on screen as on a unit-speed surface, and it stays displaced while that is
// resolved.
float levelTransition(const ReliefLevel& level, float lengthPerU, float cosThetaV, float distance,
                      float pixelsPerRadian, const TransitionSettings& settings);

// What T asks of every level at one limit-surface point seen from the eye (Becker & Max 1993,
// eq. 10 and section 2.3): the one evaluation that both the tessellator (how far to raise the
// geometry) and the shader (which renderer, which disp for theta_W) use, so geometry and shading
// never disagree. frames[i] is the geometric frame level i perturbs: frames[i + 1] =
// nextFrame(frames[i], disp_i B_i), the surface as raised; V and the distance are taken from the
// limit point, never from the hit.
struct LevelTransitions {
  int count = 0;  // levels evaluated: all, or for the shader up to the first BRDF-alone level
  std::array<float, kMaxReliefLevels> T{};
  std::array<TransitionWeights, kMaxReliefLevels> weights{};
  std::array<float, kMaxReliefLevels> disp{};  // 1 in Full mode
  // frames[0 .. count]; B and H of levels 0 .. raised - 1: the rest is left unset by
  // levelTransitions (not zeroed: the struct is made for every shaded sample and vertex, and
  // zeroing its 700 bytes was 15% of levelTransitions' own time).
  std::array<SurfaceFrame, kMaxReliefLevels + 1> frames;
  int raised = 0;  // leading levels with disp > 0
  // (B_u, B_v) of levels 0 .. raised - 1 at sp.uv, as the raised frames used them: the shader
  // reuses them for its Blinn normals instead of evaluating the relief again; and their heights
  // (ReliefLevel::height), which the tessellator's offsets reuse. A band of an image raised in
  // part (0 < disp < 1) gives those of its partial sum (ReliefLevel::partialSum): its finer bands
  // stay flat, and the geometry rises by disp times the sum whose tables remap its normal through
  // theta_W, as that remap assumes (raising the band alone leaves the sum's finer part out of the
  // geometry: a 1/f map on a plane is then 1.3% too dark where its bands are partly raised).
  std::array<Vec2, kMaxReliefLevels> B;
  std::array<float, kMaxReliefLevels> H;
};

// With lights (render.shadows), the shadow terminator is treated like the silhouette (Becker & Max
// section 4.2): T_i = max over V and each light's L of (nu_i - D) / (|cos theta| + eps), so relief
// near a light's terminator is displaced (its shadows then come from real shadow rays) as soon as
// it spans enough pixels, while far relief (nu < D) keeps the view's own T.
// Shading: the evaluation stops after the first level whose T selects the BRDF table alone
// (weights.brdf == 1, so count is that level + 1): the table stands for every finer level, and the
// shader reads nothing of them. Geometry: every level (the tessellator's offsets need all frames).
// Offsets: as Geometry, less what the offsets of ReliefDisplacement do not read: when the last
// level is raised, its B and frames[count] (the frame it raises, which no finer level perturbs)
// are left unset, and its height comes from the source's height alone (the same bits).
enum class TransitionsFor { Geometry, Shading, Offsets };
// `coord` is where the levels are evaluated (reliefChart); the form without it evaluates relief
// over (u, v) at sp.uv. lengthPerU > 0 replaces the point's own max(|P_u|, |P_v|) in T: the
// mesh's UvSpeed there, continuous across faces (relief over (u, v) only; the tessellator and the
// shader pass the same).
LevelTransitions levelTransitions(const MaterialRelief& relief, const SurfacePoint& sp,
                                  const ReliefCoord& coord, const Vec3& eye, float pixelsPerRadian,
                                  const TransitionSettings& settings, DisplacementMode mode,
                                  std::span<const Light> lights = {},
                                  TransitionsFor use = TransitionsFor::Geometry,
                                  float lengthPerU = 0.0f);
inline LevelTransitions levelTransitions(const MaterialRelief& relief, const SurfacePoint& sp,
                                         const Vec3& eye, float pixelsPerRadian,
                                         const TransitionSettings& settings, DisplacementMode mode,
                                         std::span<const Light> lights = {},
                                         TransitionsFor use = TransitionsFor::Geometry) {
  return levelTransitions(relief, sp, ReliefCoord{sp.uv}, eye, pixelsPerRadian, settings, mode,
                          lights, use);
}

// Where an object's points lie in the space of its material's solid relief (docs/solid-relief.md):
// P_solid = linear * P_world + offset. Inactive for relief over (u, v).
struct SolidSpace {
  bool active = false;
  Mat3 linear{1.0f};
  Vec3 offset{0.0f};
  float lengthPerUnit = 1.0f;  // world length of one unit of solid space
};

// The solid space of an object with this transform (object space, or world space when the
// material's relief says so); a warning in `warning` when the transform scales unevenly (the
// relief is then stretched in world space, while its tables assume it isotropic).
SolidSpace solidSpace(const Material& material, const Mat4& transform, std::string* warning);

// The limit-surface point as the relief sees it, and where its levels are evaluated. For relief
// over (u, v): sp itself and coord {sp.uv}. For solid relief, a local chart that does not depend
// on the mesh's parameterization: P_u and P_v become an orthonormal pair in the tangent plane
// (along P_u's tangent part, or any where P_u degenerates) scaled to the world length of one unit
// of solid space, so T, the tables' metric and the frames of every level see a unit-speed
// isotropic surface; coord holds the point and those tangents in solid space.
SurfacePoint reliefChart(const SurfacePoint& sp, const SolidSpace& space, ReliefCoord& coord);

}  // namespace meso
