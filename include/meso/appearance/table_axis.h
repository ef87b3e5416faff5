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
TableAxis locateOnAxis(float x, float lo, float hi, int n);

// The view azimuth phiV between the centres 2 pi (m + 1/2) / n of n periodic view-azimuth slices
// (slice n - 1 neighbours slice 0); with one slice, slice 0.
TableAxis locateViewAzimuth(float phiV, int n);

// An angle in [-pi, pi] (pi stays pi, so the last node of a signed axis is reachable).
float wrapAngle(float a);

// The unit direction at polar angle theta and azimuth phi about +z.
inline Vec3 polarDirection(float theta, float phi) {
  const float s = std::sin(theta);
  return {s * std::cos(phi), s * std::sin(phi), std::cos(theta)};
}

// Multilinear interpolation over the 16 corners of (theta_V a, view azimuth m, b, c) of a table
// whose view slice is a.i * numPhiV + m.i; entry(slice, ib, ic) returns a Value with diffuse and
// specular members. Corners of weight 0 are not read.
template <typename Value, typename Entry>
Value interpolateTable(const TableAxis& a, const TableAxis& m, int numPhiV, const TableAxis& b,
                       const TableAxis& c, const Entry& entry) {
  Value out{0.0f, 0.0f};
  for (int corner = 0; corner < 16; ++corner) {
    const float w = ((corner & 1) ? a.w : 1.0f - a.w) * ((corner & 2) ? m.w : 1.0f - m.w) *
                    ((corner & 4) ? b.w : 1.0f - b.w) * ((corner & 8) ? c.w : 1.0f - c.w);
    if (w == 0.0f) continue;
    const int k = ((corner & 1) ? a.i1 : a.i0) * numPhiV + ((corner & 2) ? m.i1 : m.i0);
    const Value e = entry(k, (corner & 4) ? b.i1 : b.i0, (corner & 8) ? c.i1 : c.i0);
    out.diffuse += w * e.diffuse;
    out.specular += w * e.specular;
  }
  return out;
}

}  // namespace meso
