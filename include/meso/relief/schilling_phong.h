// Schilling, "Antialiasing of Bump Maps", Appendix A: the roughness-modified Blinn-Phong.
// The highlight widens by the roughness (slope covariance) that filtering removed.
#pragma once

#include "meso/core/math.h"
#include "meso/relief/slope_covariance.h"

namespace meso {

// cos^2(alpha') = cos^2(alpha) / (|D^-1 d|^2 + cos^2(alpha)), where alpha is the angle between the
// unit normal n and the unit halfway vector h, cos^2(alpha) = 1 - |d|^2, and d is the projection of
// n - h onto the orthonormal tangent basis (e1, e2) in which D (the roughness factor of the
// normal's offset vectors) is expressed. Equivalently tan^2(alpha') = s^T K^-1 s for the halfway
// slope s = d / cos(alpha): a Gaussian slope distribution with covariance K. Reduces to the
// isotropic form for D = lambda_1 I. Returns a value in [0, 1]; never NaN (singular D is
// regularized).
float modifiedCos2Alpha(const Vec3& n, const Vec3& h, const Vec3& e1, const Vec3& e2,
                        const RoughnessFactor& D);
// The same from d and cos^2(alpha) directly.
float modifiedCos2Alpha(Vec2 d, float cos2Alpha, const RoughnessFactor& D);
// Isotropic form, with c2 = cos^2(alpha): cos^2(alpha') = lambda1^2 c2 / (1 - c2 + lambda1^2 c2).
float modifiedCos2AlphaIsotropic(float cos2Alpha, float lambda1);
// The highlight (cos alpha')^m = (cos^2 alpha')^(m / 2), with Schilling's constant exponent m.
float schillingSpecular(float cos2AlphaPrime, float m);

// The slope covariance K of (f_u, f_v) (per unit of u and v, as B_u, B_v) expressed as the
// covariance of the unit normal's offsets in the orthonormal tangent basis (e1, e2): Schilling's
// "natural system" n' = n + f_u s_u + f_v s_v with s_u = (n x P_v) / |P_u x P_v|,
// s_v = (P_u x n) / |P_u x P_v|, so the result is E K E^T with E = [e_a . s_b].
SlopeCovariance tangentCovariance(const SlopeCovariance& K, const Vec3& Pu, const Vec3& Pv,
                                  const Vec3& e1, const Vec3& e2);
// The roughness that makes the modified highlight with exponent m match a plain Blinn-Phong
// (n.h)^phongExponent for a smooth surface: K = (m / phongExponent) I, since then
// (1 + tan^2(alpha) phongExponent / m)^(-m/2) -> exp(-phongExponent tan^2(alpha) / 2), which is
// about cos^phongExponent(alpha). Add it to the filtered roughness.
SlopeCovariance phongCovariance(float phongExponent, float m);

}  // namespace meso
