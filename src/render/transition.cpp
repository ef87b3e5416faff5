// Becker & Max 1993, eq. (10) and section 4.2.
#include "meso/render/transition.h"

#include "meso/core/error.h"

#include <algorithm>
#include <cmath>

namespace meso {

void validateTransitionSettings(const TransitionSettings& s, const char* where) {
  const float all[] = {s.D, s.eps, s.e1, s.e2, s.e3, s.e4};
  for (float v : all)
    if (!std::isfinite(v))
      throw Error(std::string(where) + ": transition settings must be finite numbers");
  if (s.D < 0.0f) throw Error(std::string(where) + ": D must be >= 0");
  if (s.eps < 0.0f) throw Error(std::string(where) + ": eps must be >= 0");
  if (!thresholdsOrdered(s.e1, s.e2, s.e3, s.e4))
    throw Error(std::string(where) + ": thresholds must satisfy " + kThresholdOrder + ", got " +
                std::to_string(s.e1) + ", " + std::to_string(s.e2) + ", " + std::to_string(s.e3) +
                ", " + std::to_string(s.e4));
}

float transitionParameter(float wavelength, float pixelsPerRadian, float distance, float cosThetaV,
                          const TransitionSettings& s) {
  constexpr float kLimit = 1e6f;
  // A camera touching the surface sees the wavelength over infinitely many pixels: saturate.
  const float nu = distance > 0.0f ? wavelength * pixelsPerRadian / distance : kLimit;
  const float denom = std::clamp(cosThetaV, 0.0f, 1.0f) + s.eps;
  const float num = std::min(nu, kLimit) - s.D;
  if (denom <= 0.0f) return num > 0.0f ? kLimit : (num < 0.0f ? -kLimit : 0.0f);
  return std::clamp(num / denom, -kLimit, kLimit);
}

float ramp(float t, float a, float b) {
  const float x = std::clamp((t - a) / (b - a), 0.0f, 1.0f);
  return x * x * (3.0f - 2.0f * x);
}

TransitionWeights transitionWeights(float T, const TransitionSettings& s) {
  TransitionWeights w;
  w.redistribution = ramp(T, s.e1, s.e2);
  w.brdf = 1.0f - w.redistribution;
  w.disp = ramp(T, s.e3, s.e4);
  return w;
}

}  // namespace meso
