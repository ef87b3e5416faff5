// Becker & Max 1993, section 2.2: B_u by eq. (3) and by the quadratic C1 weights.
#include "meso/relief/bump_derivatives.h"

#include "meso/relief/height_table.h"

namespace meso {
namespace {

// The eight texels both schemes read (section 2.2): columns i-1..i+2 linearly interpolated in v
// (for B_u) and rows j-1..j+2 linearly interpolated in u (for B_v).
struct Neighbourhood {
  float col[4];  // B[i - 1 + m, y], linear in y
  float row[4];  // B[x, j - 1 + m], linear in x
  float tx, ty;
};

Neighbourhood gather(const HeightTable& t, double x, double y) {
  const TexelTaps tx = t.tapsX(x), ty = t.tapsY(y);
  const float* data = t.texels().data();
  const size_t w = static_cast<size_t>(t.width());
  const float *r1 = data + ty.k[1] * w, *r2 = data + ty.k[2] * w;
  Neighbourhood n;
  for (int m = 0; m < 4; ++m) {
    const float* r = data + ty.k[m] * w;
    n.col[m] = (1.0f - ty.t) * r1[tx.k[m]] + ty.t * r2[tx.k[m]];
    n.row[m] = (1.0f - tx.t) * r[tx.k[1]] + tx.t * r[tx.k[2]];
  }
  n.tx = tx.t;
  n.ty = ty.t;
  return n;
}

// The paper's weighted sum, rearranged over first differences: with a0 = (1 - d)^2 / 2,
// a2 = d^2 / 2, a1 = 1 - a0 - a2 (the quadratic B-spline), sum w_m B[m] = a0 (B1 - B0) +
// a1 (B2 - B1) + a2 (B3 - B2) since w0 = -a0, w1 = a0 - a1, w2 = a1 - a2, w3 = a2. Same value, but
// a ramp gives its slope to rounding and the two sides of a knot agree to rounding.
inline float quadratic(const float b[4], float d) {
  const float a0 = 0.5f * (1.0f - d) * (1.0f - d), a2 = 0.5f * d * d, a1 = 1.0f - a0 - a2;
  return a0 * (b[1] - b[0]) + a1 * (b[2] - b[1]) + a2 * (b[3] - b[2]);
}

// (bilinear(x + 1) - bilinear(x - 1)) / 2 over the same taps.
inline float central(const float b[4], float d) {
  return 0.5f * ((1.0f - d) * (b[2] - b[0]) + d * (b[3] - b[1]));
}

}  // namespace

void quadraticDerivativeWeights(float du, float w[4]) {
  const float d2 = du * du;
  w[0] = -0.5f * d2 + du - 0.5f;
  w[1] = 1.5f * d2 - 2.0f * du;
  w[2] = -1.5f * d2 + du + 0.5f;
  w[3] = 0.5f * d2;
}

Vec2 quadraticDerivatives(const HeightTable& table, double x, double y) {
  const Neighbourhood n = gather(table, x, y);
  return {quadratic(n.col, n.tx), quadratic(n.row, n.ty)};
}

Vec2 centralDifferenceDerivatives(const HeightTable& table, double x, double y) {
  const Neighbourhood n = gather(table, x, y);
  return {central(n.col, n.tx), central(n.row, n.ty)};
}

Vec2 bumpDerivatives(const HeightTable& table, double x, double y, BumpDerivativeMethod method) {
  return method == BumpDerivativeMethod::Quadratic ? quadraticDerivatives(table, x, y)
                                                   : centralDifferenceDerivatives(table, x, y);
}

}  // namespace meso
