// meso's continuous chart of faces that Bfr parameterizes by quad sub-faces (limit_surface_impl.h).
#include "limit_surface_impl.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace meso {

using OpenSubdiv::Bfr::Parameterization;

void appendFaceChart(int n, std::vector<Vec2>& chart) {
  if (n == 3) {
    chart.insert(chart.end(), {Vec2(0.0f), Vec2(1.0f, 0.0f), Vec2(0.0f, 1.0f), Vec2(1.0f / 3.0f)});
    return;
  }
  // Edge 0 at the bottom running along +s, as for quads.
  for (int k = 0; k < n; ++k) {
    const double theta =
        -0.5 * std::numbers::pi - std::numbers::pi / n + 2.0 * std::numbers::pi * k / n;
    chart.emplace_back(0.5 + 0.5 * std::cos(theta), 0.5 + 0.5 * std::sin(theta));
  }
  chart.emplace_back(0.5f, 0.5f);
}

Vec2 LimitSurface::Impl::chartToBfr(int face, Vec2 st, glm::mat2& jacobian) const {
  const Face& f = faces[face];
  if (f.chartOffset < 0) {
    jacobian = glm::mat2(1.0f);
    if (f.param.GetType() == Parameterization::TRI) {
      st = glm::max(st, Vec2(0.0f));
      const float sum = st.x + st.y;
      return sum > 1.0f ? st / sum : st;
    }
    return glm::clamp(st, Vec2(0.0f), Vec2(1.0f));
  }
  // The 2N triangles of the fan around the centre split the chart into wedges: pick the wedge
  // containing st. A point outside the polygon is projected radially onto its boundary, which keeps
  // the clamp continuous.
  const int n = f.param.GetFaceSize();
  const Vec2* v = &chartPoints[f.chartOffset];
  const Vec2 c = v[n];
  float best = -1e30f;
  int bestSub = 0;
  bool bestLower = true;
  Vec2 bestLambda(0.0f);
  glm::mat2 bestInverse(1.0f);
  for (int i = 0; i < n; ++i) {
    const Vec2 vi = v[i], mNext = 0.5f * (vi + v[(i + 1) % n]);
    const Vec2 mPrev = 0.5f * (vi + v[(i + n - 1) % n]);
    for (bool lower : {true, false}) {
      // lower: (C, V_i, M_i) <-> (1, 1), (0, 0), (1, 0); upper: (C, M_i-1, V_i) <-> (1, 1), (0, 1),
      // (0, 0) in the sub-face's normalized coordinates.
      const glm::mat2 e = lower ? glm::mat2(vi - c, mNext - c) : glm::mat2(mPrev - c, vi - c);
      const glm::mat2 inv = glm::inverse(e);
      const Vec2 lambda = inv * (st - c);
      const float m = std::min(lambda.x, lambda.y);
      if (m > best)
        best = m, bestSub = i, bestLower = lower, bestLambda = lambda, bestInverse = inv;
    }
  }
  const float outer = bestLambda.x + bestLambda.y;
  if (outer > 1.0f) bestLambda /= outer;
  const glm::mat2 local = bestLower ? glm::mat2(Vec2(-1.0f, -1.0f), Vec2(0.0f, -1.0f))
                                    : glm::mat2(Vec2(-1.0f, 0.0f), Vec2(-1.0f, -1.0f));
  const Vec2 ab = glm::clamp(Vec2(1.0f) + local * bestLambda, Vec2(0.0f), Vec2(1.0f));
  // Normalized sub-face coordinates are twice Bfr's tile coordinates.
  jacobian = 0.5f * local * bestInverse;
  Vec2 uv;
  f.param.ConvertNormalizedSubFaceToCoord(bestSub, &ab.x, &uv.x);
  return uv;
}

Vec2 LimitSurface::Impl::bfrToChart(int face, Vec2 bfrUv) const {
  const Face& f = faces[face];
  if (f.chartOffset < 0) return bfrUv;
  const int n = f.param.GetFaceSize();
  const Vec2* v = &chartPoints[f.chartOffset];
  Vec2 ab;
  const int i = f.param.ConvertCoordToNormalizedSubFace(&bfrUv.x, &ab.x);
  ab = glm::clamp(ab, Vec2(0.0f), Vec2(1.0f));
  const Vec2 vi = v[i], c = v[n];
  if (ab.x >= ab.y) {
    const Vec2 mNext = 0.5f * (vi + v[(i + 1) % n]);
    return (1.0f - ab.x) * vi + (ab.x - ab.y) * mNext + ab.y * c;
  }
  const Vec2 mPrev = 0.5f * (vi + v[(i + n - 1) % n]);
  return (1.0f - ab.y) * vi + (ab.y - ab.x) * mPrev + ab.x * c;
}

}  // namespace meso
