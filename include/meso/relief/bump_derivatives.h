// Becker & Max 1993, section 2.2 and eq. 3: the bump derivatives B_u, B_v of a height table.
// Central differences of bilinear lookups (eq. 3) or the paper's quadratic (C1 B-spline) weights.
#pragma once

#include "meso/core/math.h"

namespace meso {

class HeightTable;

enum class BumpDerivativeMethod {
  // The paper's choice (default): the derivative of the C2 cubic B-spline whose control points are
  // the texels. B_u is a C1 quadratic spline in u (no Mach bands), exact for linear ramps.
  Quadratic,
  // Eq. (3) with epsilon = one texel: (B[x + 1] - B[x - 1]) / 2 of bilinear lookups. B_u is
  // continuous but only piecewise linear: its slope jumps at every texel centre.
  CentralDifference,
};

// The paper's weights of B[i - 1], B[i], B[i + 1], B[i + 2] at du = x - floor(x) in [0, 1), where
// texel coordinates x have the texel centres on the integers (i = floor(x)). They sum to 0.
void quadraticDerivativeWeights(float du, float w[4]);

// Texel coordinates: x = u W - 0.5, y = v H - 0.5 for tile coordinates (u, v), so texel (i, j) is
// centred at (i, j). Results are (dB/dx, dB/dy) in table units per texel. Doubles, so that probes a
// hair away from a knot (x = k +- 1e-7) are representable. Allocation-free; NaN coordinates give a
// finite value.
Vec2 quadraticDerivatives(const HeightTable& table, double x, double y);
Vec2 centralDifferenceDerivatives(const HeightTable& table, double x, double y);
Vec2 bumpDerivatives(const HeightTable& table, double x, double y, BumpDerivativeMethod method);

}  // namespace meso
