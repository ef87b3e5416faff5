// Schilling, "Antialiasing of Bump Maps", roughness pyramid: K and its factor (d1, d2, d3).
// K is the covariance of slope (offset) vectors (f_u, f_v); D D^T = K.
#pragma once

#include "meso/core/math.h"

namespace meso {

// K = [[a, b], [b, c]]: the covariance of (f_u, f_v) (or of normal offsets in a tangent basis).
struct SlopeCovariance {
  float a = 0.0f, b = 0.0f, c = 0.0f;

  SlopeCovariance& operator+=(const SlopeCovariance& o) {
    a += o.a, b += o.b, c += o.c;
    return *this;
  }
  friend SlopeCovariance operator+(SlopeCovariance x, const SlopeCovariance& y) { return x += y; }
  friend SlopeCovariance operator*(float s, const SlopeCovariance& k) {
    return {s * k.a, s * k.b, s * k.c};
  }
};

// D = [[d1, d2], [0, d3]] with D D^T = K:  d3 = sqrt(c), d2 = b / sqrt(c), d1 = sqrt(a - b^2 / c),
// d1 and d3 >= 0. Stores standard deviations rather than variances (uniform accuracy), and D is
// what an anisotropic filter needs.
struct RoughnessFactor {
  float d1 = 0.0f, d2 = 0.0f, d3 = 0.0f;
};

// The factor of K; K is clamped to positive semi-definite first. c = 0 gives d2 = 0, d1 = sqrt(a).
RoughnessFactor roughnessFactor(const SlopeCovariance& K);
// K = D D^T = [[d1^2 + d2^2, d2 d3], [d2 d3, d3^2]].
SlopeCovariance covarianceOf(const RoughnessFactor& D);
// lambda_1: the standard deviation along the direction of largest variance, sqrt of K's largest
// eigenvalue (Schilling's isotropic roughness).
float largestStdDev(const SlopeCovariance& K);

}  // namespace meso
