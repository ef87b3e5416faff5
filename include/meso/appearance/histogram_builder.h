// Becker & Max 1993, section 2.1: visible-normal histograms measured by tracing orthographic rays
// at a periodic tile of the fully displaced relief, neighbour tiles occluding (DESIGN.md section
// 4).
#pragma once

#include "meso/appearance/visible_normal_histogram.h"
#include "meso/core/math.h"

#include <cstdint>

namespace meso {

// One relief level as the table builders see it: a height field over the unit tile, periodic with
// period 1 in x and y, in tile units (world height times the tiling scale S divided by the
// parameterization's length per unit u, which the tables take as 1). Normals are the Blinn normals
// of a flat patch, normalize(-dh/dx, -dh/dy, 1).
class PeriodicRelief {
 public:
  virtual ~PeriodicRelief() = default;
  virtual float height(float x, float y) const = 0;
  virtual Vec2 gradient(float x, float y) const = 0;
  // Identifies the relief for the table cache: a hash of everything that shapes height().
  virtual uint64_t fingerprint() const = 0;
};

// The area-preserving shape of a parameterization, Becker & Max's stretched (u, v)
// (docs/metric.md): tangent coordinates of the tile (x, y) map to the surface's orthonormal frame
// (P_u direction first) by the upper triangular [[a, b], [0, 1 / a]]. Identity: isotropic,
// orthogonal uv.
struct MetricShape {
  float a = 1.0f;
  float b = 0.0f;
  bool identity() const { return a == 1.0f && b == 0.0f; }
  bool operator==(const MetricShape&) const = default;
};

struct HistogramSettings {
  HistogramResolution resolution;
  int azimuths = 32;         // phi_V directions per theta_V slice
  int raysPerView = 2048;    // rays per (theta_V, phi_V)
  int meshResolution = 192;  // quads per tile side of the traced height field
  uint64_t seed = 1;
  // The relief is traced as seen on a surface of this shape: rays and normals go through the map,
  // and the histogram is of normals in that surface's frame (its view azimuths about P_u).
  MetricShape shape;
};

// Traces the histogram; deterministic for a seed whatever the thread count (slices are
// independent).
VisibleNormalHistogram buildVisibleNormalHistogram(const PeriodicRelief& relief,
                                                   const HistogramSettings& settings);

}  // namespace meso
