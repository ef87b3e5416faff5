// Becker & Max 1993, eq. (10) and section 4: the transition parameter T(d, theta_V) and the weights
// of the renderers it selects (DESIGN.md section 3).
#pragma once

#include "meso/scene/scene.h"

#include <algorithm>

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

}  // namespace meso
