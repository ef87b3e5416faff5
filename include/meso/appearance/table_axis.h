// The axes of meso's angular tables (BRDF and shadowing tables, DESIGN.md section 4): where a value
// falls between nodes, and the multilinear lookup over (theta_V, view azimuth, two more angles).
#pragma once

#include "meso/core/math.h"

#include <algorithm>
#include <cmath>

namespace meso {

// Two neighbouring nodes and the weight of the second.
struct TableAxis {
  int i0 = 0;
  int i1 = 0;
  float w = 0.0f;
};

// x on n nodes evenly spaced over [lo, hi], both ends included; clamped to the ends (non-finite x:
// the first node).
inline TableAxis locateOnAxis(float x, float lo, float hi, int n) {
  float s = std::isfinite(x) ? (x - lo) / (hi - lo) * static_cast<float>(n - 1) : 0.0f;
  s = std::clamp(s, 0.0f, static_cast<float>(n - 1));
  const int i0 = std::min(static_cast<int>(s), std::max(n - 2, 0));
  return {i0, std::min(i0 + 1, n - 1), s - static_cast<float>(i0)};
}

// The theta_V rows of a table that were built, first to last (last < 0: every row). Tables are
// built only on the rows a scene's frames can look them up at (docs/tables.md, "Only the views a
// scene needs"); lookups clamp to those rows.
struct ViewRows {
  int first = 0;
  int last = -1;
  bool all() const { return first <= 0 && last < 0; }
  bool contains(int k) const { return k >= first && (last < 0 || k <= last); }
  // The same rows on an axis refined `refine` times (node k becomes node k * refine).
  ViewRows refined(int refine) const {
    return all() ? ViewRows{} : ViewRows{first * refine, last * refine};
  }
  bool operator==(const ViewRows&) const = default;
};

// locateOnAxis, kept within the nodes `rows` of the axis (a lookup beyond them takes the nearest
// built row): on every row, the same nodes and weight as locateOnAxis.
inline TableAxis locateOnAxis(float x, float lo, float hi, int n, const ViewRows& rows) {
  if (rows.all()) return locateOnAxis(x, lo, hi, n);
  const int first = std::clamp(rows.first, 0, n - 1);
  const int last = std::clamp(rows.last, first, n - 1);
  float s = std::isfinite(x) ? (x - lo) / (hi - lo) * static_cast<float>(n - 1) : 0.0f;
  s = std::clamp(s, static_cast<float>(first), static_cast<float>(last));
  const int i0 = std::min(static_cast<int>(s), std::max(last - 1, first));
  return {i0, std::min(i0 + 1, last), s - static_cast<float>(i0)};
}

// The view azimuth phiV between the centres 2 pi (m + 1/2) / n of n periodic view-azimuth slices
// (slice n - 1 neighbours slice 0); with one slice, slice 0.
inline TableAxis locateViewAzimuth(float phiV, int n) {
  if (n <= 1) return {};
  float s = (std::isfinite(phiV) ? phiV : 0.0f) / (2.0f * kPi) * static_cast<float>(n) - 0.5f;
  s -= static_cast<float>(n) * std::floor(s / static_cast<float>(n));
  const int m0 = std::min(static_cast<int>(s), n - 1);
  return {m0, (m0 + 1) % n, std::clamp(s - static_cast<float>(m0), 0.0f, 1.0f)};
}

// An angle in [-pi, pi] (pi stays pi, so the last node of a signed axis is reachable). Angles
// already there (atan2's) return at once: fmod would give them back unchanged.
inline float wrapAngle(float a) {
  if (a >= -kPi && a <= kPi) return a;
  if (!std::isfinite(a)) return 0.0f;
  a = std::fmod(a, 2.0f * kPi);
  if (a > kPi) a -= 2.0f * kPi;
  if (a < -kPi) a += 2.0f * kPi;
  return a;
}

// The unit direction at polar angle theta and azimuth phi about +z.
inline Vec3 polarDirection(float theta, float phi) {
  const float s = std::sin(theta);
  return {s * std::cos(phi), s * std::sin(phi), std::cos(theta)};
}

// A table's values laid out as [view slice][b node][c node], diffuse and specular in two arrays;
// the view slice of (theta_V node a, view azimuth m) is a * numPhiV + m.
struct TableLayout {
  const float* diffuse = nullptr;
  const float* specular = nullptr;
  int numPhiV = 1;
  int nb = 1;  // b nodes
  int nc = 1;  // c nodes
};

// Multilinear interpolation over the 16 corners of (theta_V a, view azimuth m, b, c), evaluated as
// bilinear (b, c) interpolation in each of the (up to) four view slices around (a, m), which are
// then mixed: about a quarter of the work of summing the 16 corners one by one, the same value up
// to float rounding. A view slice of weight 0 is not read. Each interpolation is (1 - w) x + w y,
// so a lookup on a node returns the node's value exactly.
template <typename Value>
Value interpolateTable(const TableAxis& a, const TableAxis& m, const TableAxis& b,
                       const TableAxis& c, const TableLayout& t) {
  const auto mix = [](float x, float y, float w) { return (1.0f - w) * x + w * y; };
  const size_t perSlice = static_cast<size_t>(t.nb) * t.nc;
  const size_t rowB0 = static_cast<size_t>(b.i0) * t.nc, rowB1 = static_cast<size_t>(b.i1) * t.nc;
  Value out{0.0f, 0.0f};
  for (int km = 0; km < 2; ++km)
    for (int ka = 0; ka < 2; ++ka) {
      const float w = (ka ? a.w : 1.0f - a.w) * (km ? m.w : 1.0f - m.w);
      if (w == 0.0f) continue;
      const size_t slice = static_cast<size_t>(ka ? a.i1 : a.i0) * t.numPhiV + (km ? m.i1 : m.i0);
      const float* d = t.diffuse + slice * perSlice;
      const float* s = t.specular + slice * perSlice;
      const float d0 = mix(d[rowB0 + c.i0], d[rowB0 + c.i1], c.w);
      const float d1 = mix(d[rowB1 + c.i0], d[rowB1 + c.i1], c.w);
      const float s0 = mix(s[rowB0 + c.i0], s[rowB0 + c.i1], c.w);
      const float s1 = mix(s[rowB1 + c.i0], s[rowB1 + c.i1], c.w);
      out.diffuse += w * mix(d0, d1, b.w);
      out.specular += w * mix(s0, s1, b.w);
    }
  return out;
}

}  // namespace meso
