// The surface metric classes a material's tables are built for (docs/metric.md): a frame's length
// per unit of u and its area-preserving shape, and the classes that cover a surface's metrics.
#pragma once

#include "meso/appearance/histogram_builder.h"
#include "meso/core/math.h"

#include <cstddef>
#include <span>
#include <vector>

namespace meso {

// A metric class to build: isotropic length and shape.
struct MetricClass {
  float lengthPerU = 1.0f;
  MetricShape shape;
};

// The shape and length of a frame: [P_u, P_v] in the orthonormal frame (P_u / |P_u|, N x that) is
// l [[a, b], [0, 1 / a]] with l = sqrt |P_u x P_v|.
MetricClass metricOf(const Vec3& Pu, const Vec3& Pv);

// Where a surface's own metric falls between the classes: the classes of the nearest shape (in
// log a and b) whose lengths bracket the surface's, k0 and k1 (equal at the ends), mixed by w in
// log length; `nearest` is the closer one.
struct MetricPosition {
  int k0 = 0, k1 = 0, nearest = 0;
  float w = 0.0f;
};

// At most this many metric classes per material (each is a table set per level, about 11 MB and
// half a second to a few seconds to build; a UV sphere needs 15, a torus 6): a surface whose
// metric is garbage, such as a mesh so far from the origin that its float positions collapse, once
// asked for 111 classes (332 table sets, minutes to build and gigabytes to hold).
inline constexpr size_t kMaxMetricClasses = 32;
// The stretch a and shear b of a class are clamped to [1/16, 16] (a 256:1 ratio of |P_u| to
// |P_v|) and [-4, 4]; a sample beyond is looked up in the nearest class (docs/metric.md).
inline constexpr float kMaxMetricStretch = 16.0f;
inline constexpr float kMaxMetricShear = 4.0f;

// The classes for the metrics sampled on a material's surfaces: samples binned by their shape
// quantized to stepOctaves in a and stepOctaves / 2 in b; each bin's class has the bin's mean shape
// (geometric in a; exactly the identity when that is within 1e-3 of it) and metricClasses over the
// bin's range of lengths. Shapes are clamped to kMaxMetricStretch and kMaxMetricShear first. Past
// kMaxMetricClasses the step is doubled until they fit; `stepUsed` (may be null) receives the step
// that was used.
std::vector<MetricClass> metricClassesFor(std::span<const MetricClass> samples, float stepOctaves,
                                          float* stepUsed = nullptr);

// The metric classes that cover lengths per unit of u in [lo, hi]: one class at sqrt(lo hi) when
// hi / lo < 1 + 1e-3, else a geometric series from lo to hi with ratio at most 2^stepOctaves.
std::vector<float> metricClasses(float lo, float hi, float stepOctaves);

}  // namespace meso
