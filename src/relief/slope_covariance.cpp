// Schilling, "Antialiasing of Bump Maps", section "The roughness pyramid": D with D D^T = K.
#include "meso/relief/slope_covariance.h"

#include <algorithm>
#include <cmath>

namespace meso {

RoughnessFactor roughnessFactor(const SlopeCovariance& K) {
  if (!std::isfinite(K.a) || !std::isfinite(K.b) || !std::isfinite(K.c)) return {};
  const float a = std::max(K.a, 0.0f), c = std::max(K.c, 0.0f);
  const float bound = std::sqrt(a * c);  // |b| <= sqrt(a c) for a covariance
  const float b = std::clamp(K.b, -bound, bound);
  RoughnessFactor D;
  D.d3 = std::sqrt(c);
  D.d2 = D.d3 > 0.0f ? b / D.d3 : 0.0f;  // c = 0 forces b = 0: all variance along f_u
  D.d1 = std::sqrt(std::max(a - D.d2 * D.d2, 0.0f));
  return D;
}

SlopeCovariance covarianceOf(const RoughnessFactor& D) {
  return {D.d1 * D.d1 + D.d2 * D.d2, D.d2 * D.d3, D.d3 * D.d3};
}

float largestStdDev(const SlopeCovariance& K) {
  const float mean = 0.5f * (K.a + K.c), half = 0.5f * (K.a - K.c);
  const float lambda = mean + std::sqrt(half * half + K.b * K.b);
  return std::isfinite(lambda) ? std::sqrt(std::max(lambda, 0.0f)) : 0.0f;
}

}  // namespace meso
