// Schilling, "Antialiasing of Bump Maps", Appendix A: the modified Blinn-Phong model.
#include "meso/relief/schilling_phong.h"

#include <algorithm>
#include <cmath>

namespace meso {
namespace {

// The smallest standard deviation D is trusted with: a smooth surface becomes a very sharp,
// finite highlight rather than a division by zero.
constexpr float kMinStdDev = 1e-6f;

}  // namespace

float modifiedCos2Alpha(Vec2 d, float cos2Alpha, const RoughnessFactor& D) {
  if (!(cos2Alpha > 0.0f)) return 0.0f;
  cos2Alpha = std::min(cos2Alpha, 1.0f);
  // |D^-1 d|^2 by back substitution in D = [[d1, d2], [0, d3]].
  const float y2 = d.y / std::max(D.d3, kMinStdDev);
  const float y1 = (d.x - D.d2 * y2) / std::max(D.d1, kMinStdDev);
  const float q = y1 * y1 + y2 * y2;
  const float r = cos2Alpha / (q + cos2Alpha);
  return std::isfinite(r) ? std::clamp(r, 0.0f, 1.0f) : 0.0f;
}

float modifiedCos2Alpha(const Vec3& n, const Vec3& h, const Vec3& e1, const Vec3& e2,
                        const RoughnessFactor& D) {
  const float c = glm::dot(n, h);
  if (!(c > 0.0f)) return 0.0f;  // halfway vector below the surface: no highlight
  // d = projection of n - h onto (e1, e2); n is perpendicular to both.
  return modifiedCos2Alpha(Vec2(-glm::dot(h, e1), -glm::dot(h, e2)), c * c, D);
}

float modifiedCos2AlphaIsotropic(float cos2Alpha, float lambda1) {
  if (!(cos2Alpha > 0.0f)) return 0.0f;
  cos2Alpha = std::min(cos2Alpha, 1.0f);
  const float l2 = lambda1 * lambda1 * cos2Alpha;
  const float den = (1.0f - cos2Alpha) + l2;
  if (!(den > 0.0f)) return 1.0f;  // no roughness and alpha = 0: the mirror direction itself
  const float r = l2 / den;
  return std::isfinite(r) ? std::clamp(r, 0.0f, 1.0f) : 0.0f;
}

float schillingSpecular(float cos2AlphaPrime, float m) {
  return std::pow(std::clamp(std::isfinite(cos2AlphaPrime) ? cos2AlphaPrime : 0.0f, 0.0f, 1.0f),
                  0.5f * m);
}

SlopeCovariance tangentCovariance(const SlopeCovariance& K, const Vec3& Pu, const Vec3& Pv,
                                  const Vec3& e1, const Vec3& e2) {
  const Vec3 N = glm::cross(Pu, Pv);
  const float len = glm::length(N);
  if (!(len > 1e-30f) || !std::isfinite(len)) return K;
  const Vec3 n = N / len, su = glm::cross(n, Pv) / len, sv = glm::cross(Pu, n) / len;
  const float e00 = glm::dot(e1, su), e01 = glm::dot(e1, sv), e10 = glm::dot(e2, su),
              e11 = glm::dot(e2, sv);
  return {e00 * e00 * K.a + 2.0f * e00 * e01 * K.b + e01 * e01 * K.c,
          e00 * e10 * K.a + (e00 * e11 + e01 * e10) * K.b + e01 * e11 * K.c,
          e10 * e10 * K.a + 2.0f * e10 * e11 * K.b + e11 * e11 * K.c};
}

SlopeCovariance phongCovariance(float phongExponent, float m) {
  const float v = phongExponent > 0.0f ? m / phongExponent : 0.0f;
  return {v, 0.0f, v};
}

}  // namespace meso
