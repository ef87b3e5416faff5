// Becker & Max 1993, eq. (10) and section 4: the transition parameter T(d, theta_V) and the weights
// of the renderers it selects (DESIGN.md section 3).
#pragma once

#include "meso/scene/scene.h"

namespace meso {

// Throws meso::Error naming `where` (e.g. "render.thresholds") unless e1 < e2 < 0 < e3 < e4, D >=
// 0, eps >= 0 and all are finite.
void validateTransitionSettings(const TransitionSettings& s, const char* where);

// T_i = (nu_i - D) / (cos(theta_V) + eps) with nu_i = lambda_i * p / d the number of pixels the
// level's shortest wavelength spans at distance d (p: pixels per radian). cosThetaV is clamped to
// [0, 1]; with eps = 0 at cos theta_V = 0 the result is clamped to +-1e6 instead of dividing by
// zero.
float transitionParameter(float wavelength, float pixelsPerRadian, float distance, float cosThetaV,
                          const TransitionSettings& s);

// The C1 ramp used for every blend: 0 at a, 1 at b, smoothstep between (derivative 0 at both ends,
// so weights are continuous in T with a continuous slope).
float ramp(float t, float a, float b);

// What T asks of one level. Weights sum to 1 between brdf and the bump-based renderers; disp is the
// fraction of the relief height raised as geometry (0: flat, 1: fully displaced).
struct TransitionWeights {
  float brdf = 0.0f;            // weight of the BRDF table intensity (T < e2)
  float redistribution = 0.0f;  // weight of redistribution / partial / full displacement (1 - brdf)
  float disp = 0.0f;            // ramp(T; e3, e4)
};

TransitionWeights transitionWeights(float T, const TransitionSettings& s);

}  // namespace meso
