// meso's continuous chart of faces that Bfr parameterizes by quad sub-faces (limit_surface_impl.h).
#include "limit_surface_impl.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace meso {

using OpenSubdiv::Bfr::Parameterization;

namespace {

// The kite of sub-face i: (0, 0) at V_i, (1, 0) at M_i (towards V_i+1), (1, 1) at the centre C,
// (0, 1) at M_i-1, with the bilinear map between.
struct Kite {
  Vec2 p00, p10, p11, p01;
  Vec2 at(Vec2 ab) const {
    return (1.0f - ab.x) * (1.0f - ab.y) * p00 + ab.x * (1.0f - ab.y) * p10 + ab.x * ab.y * p11 +
           (1.0f - ab.x) * ab.y * p01;
  }
  // d(at)/d(a, b) as columns.
  glm::mat2 derivative(Vec2 ab) const {
    return glm::mat2((1.0f - ab.y) * (p10 - p00) + ab.y * (p11 - p01),
                     (1.0f - ab.x) * (p01 - p00) + ab.x * (p11 - p10));
  }
  // (a, b) of st, clamped to the unit square, and d(a, b)/d(st) there. The chart's kites are
  // convex, so the bilinear map is one to one on them: of the two roots of its inverse (a quadratic
  // in b), the one nearer the unit square, then one Newton step for the float rounding.
  Vec2 inverse(Vec2 st, glm::mat2& dAbDst) const {
    const glm::dvec2 e(p10 - p00), g(p01 - p00), k(p00 - p10 + p11 - p01), h(st - p00);
    const auto cross = [](glm::dvec2 x, glm::dvec2 y) { return x.x * y.y - x.y * y.x; };
    // h = a (e + b k) + b g: the cross product with e + b k removes a.
    const double k2 = cross(k, g), k1 = cross(e, g) + cross(h, k), k0 = cross(h, e);
    const auto withA = [&](double b) {
      const glm::dvec2 dir = e + b * k, rest = h - b * g;
      const double a = std::abs(dir.x) > std::abs(dir.y) ? rest.x / dir.x : rest.y / dir.y;
      return glm::dvec2(a, b);
    };
    const auto outside = [](glm::dvec2 ab) {
      const glm::dvec2 d = glm::max(glm::max(-ab, ab - 1.0), glm::dvec2(0.0));
      return std::isfinite(ab.x) && std::isfinite(ab.y) ? d.x + d.y : 1e300;
    };
    glm::dvec2 best = withA(std::abs(k1) > 0.0 ? -k0 / k1 : 0.0);
    if (std::abs(k2) > 1e-12 * std::abs(k1)) {
      const double w = std::sqrt(std::max(k1 * k1 - 4.0 * k0 * k2, 0.0));
      best = withA((-k1 + w) / (2.0 * k2));
      const glm::dvec2 other = withA((-k1 - w) / (2.0 * k2));
      if (outside(other) < outside(best)) best = other;
    }
    if (!(outside(best) < 1e300)) best = glm::dvec2(0.5);
    Vec2 ab(glm::clamp(best, glm::dvec2(-1.0), glm::dvec2(2.0)));
    ab += glm::inverse(derivative(ab)) * (st - at(ab));  // one Newton step
    ab = glm::clamp(ab, Vec2(0.0f), Vec2(1.0f));
    dAbDst = glm::inverse(derivative(ab));
    return ab;
  }
};

Kite kiteOf(const Vec2* v, int n, int i) {
  return {v[i], 0.5f * (v[i] + v[(i + 1) % n]), v[n], 0.5f * (v[i] + v[(i + n - 1) % n])};
}

// The kite whose sector around the centre holds st: from the ray through M_i-1 counter-clockwise
// to the ray through M_i (the chart is counter-clockwise).
int chartSector(const Vec2* v, int n, Vec2 st) {
  const Vec2 c = v[n], d = st - c;
  for (int i = 0; i < n; ++i) {
    const Kite k = kiteOf(v, n, i);
    if (cross2(k.p01 - c, d) >= 0.0f && cross2(d, k.p10 - c) >= 0.0f) return i;
  }
  return 0;  // st at the centre, or NaN
}

}  // namespace

void appendFaceChart(int n, const Vec3* corners, std::vector<Vec2>& chart) {
  if (n == 3) {
    // The triangle's own shape, scaled to the unit right triangle's area (one half), edge 0 along
    // +s: a flat triangle's chart is then similar to it (its relief is isotropic, of the identity
    // metric shape). The unit right triangle where the triangle is degenerate.
    const glm::dvec3 e0 = glm::dvec3(corners[1]) - glm::dvec3(corners[0]);
    const glm::dvec3 e1 = glm::dvec3(corners[2]) - glm::dvec3(corners[0]);
    const double l0 = glm::length(e0), twiceArea = glm::length(glm::cross(e0, e1));
    if (l0 > 0.0 && twiceArea > 1e-6 * l0 * glm::length(e1) && std::isfinite(twiceArea)) {
      const double scale = 1.0 / std::sqrt(twiceArea);
      const Vec2 v1(static_cast<float>(l0 * scale), 0.0f);
      const Vec2 v2(static_cast<float>(glm::dot(e0, e1) / l0 * scale),
                    static_cast<float>(twiceArea / l0 * scale));
      chart.insert(chart.end(), {Vec2(0.0f), v1, v2, (v1 + v2) / 3.0f});
      return;
    }
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
    return glm::clamp(st, Vec2(0.0f), Vec2(1.0f));
  }
  if (f.param.GetType() == Parameterization::TRI) {
    // A Loop triangle: Bfr's (u, v) are the barycentric coordinates of st on the chart triangle.
    const Vec2* v = chartPoints(face);
    jacobian = glm::inverse(glm::mat2(v[1] - v[0], v[2] - v[0]));
    Vec2 uv = glm::max(jacobian * (st - v[0]), Vec2(0.0f));
    const float sum = uv.x + uv.y;
    return sum > 1.0f ? uv / sum : uv;
  }
  // Sub-face i is the kite (V_i, M_i, C, M_i-1) of the chart, mapped bilinearly onto the
  // sub-face's normalized square: pick the kite whose sector around the centre holds st, invert
  // its bilinear map there. A point outside the polygon is projected radially onto its boundary,
  // which keeps the clamp continuous.
  const int n = f.param.GetFaceSize();
  const Vec2* v = chartPoints(face);
  const int i = chartSector(v, n, st);
  const Kite kite = kiteOf(v, n, i);
  const Vec2 c = kite.p11, d = st - c;
  for (const auto& [from, to] : {std::pair(kite.p00, kite.p10), std::pair(kite.p01, kite.p00)}) {
    const Vec2 edge = to - from;
    const float den = cross2(d, edge);
    if (!(std::abs(den) > 0.0f)) continue;
    const float t = cross2(from - c, edge) / den, u = cross2(from - c, d) / den;
    if (u >= 0.0f && u <= 1.0f && t > 0.0f && t < 1.0f) st = c + t * d;
  }
  glm::mat2 dAbDst;
  const Vec2 ab = kite.inverse(st, dAbDst);
  // Normalized sub-face coordinates are twice Bfr's tile coordinates.
  jacobian = 0.5f * dAbDst;
  Vec2 uv;
  f.param.ConvertNormalizedSubFaceToCoord(i, &ab.x, &uv.x);
  return uv;
}

Vec2 LimitSurface::Impl::bfrToChart(int face, Vec2 bfrUv) const {
  const Face& f = faces[face];
  if (f.chartOffset < 0) return bfrUv;
  if (f.param.GetType() == Parameterization::TRI) {
    const Vec2* v = chartPoints(face);
    return v[0] + bfrUv.x * (v[1] - v[0]) + bfrUv.y * (v[2] - v[0]);
  }
  const int n = f.param.GetFaceSize();
  Vec2 ab;
  const int i = f.param.ConvertCoordToNormalizedSubFace(&bfrUv.x, &ab.x);
  return kiteOf(chartPoints(face), n, i).at(glm::clamp(ab, Vec2(0.0f), Vec2(1.0f)));
}

}  // namespace meso
