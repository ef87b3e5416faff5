// The metric classes of docs/metric.md (metric_classes.h).
#include "meso/appearance/metric_classes.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace meso {

MetricClass metricOf(const Vec3& Pu, const Vec3& Pv) {
  MetricClass m;
  const float lu = glm::length(Pu);
  const float area = glm::length(glm::cross(Pu, Pv));
  if (!(lu > 0.0f) || !(area > 0.0f) || !std::isfinite(area) || !std::isfinite(lu)) return m;
  m.lengthPerU = std::sqrt(area);
  m.shape.a = lu / m.lengthPerU;
  m.shape.b = glm::dot(Pv, Pu / lu) / m.lengthPerU;
  return m;
}

namespace {

// metricClassesFor at one step.
std::vector<MetricClass> binnedClasses(std::span<const MetricClass> samples, float stepOctaves) {
  // One bin per quantized shape; its class takes the mean shape of the samples in it (log a, b),
  // so that a surface of a single shape (a stretched or sheared plane) gets tables of exactly its
  // own: at the quantized shape a 10:1 stretch was 6% off, and its BRDF image 1.4% darker.
  struct Range {
    MetricShape bin;
    double logA = 0.0, b = 0.0;
    int count = 0;
    float lo = std::numeric_limits<float>::infinity(), hi = 0.0f;
  };
  std::vector<Range> ranges;
  const float step = std::max(stepOctaves, 1e-3f);
  // The last shape binned and what it adds: a grid's faces repeat one shape, whose logarithms and
  // bin are then found once (the same sums, added in the same order).
  MetricShape last{-1.0f, 0.0f};
  size_t lastRange = 0;
  double lastLogA = 0.0, lastB = 0.0;
  for (MetricClass m : samples) {
    if (!(m.lengthPerU > 0.0f) || !std::isfinite(m.lengthPerU) || !std::isfinite(m.shape.a) ||
        !std::isfinite(m.shape.b) || !(m.shape.a > 0.0f))
      continue;
    if (!(m.shape == last)) {
      last = m.shape;
      m.shape.a = std::clamp(m.shape.a, 1.0f / kMaxMetricStretch, kMaxMetricStretch);
      m.shape.b = std::clamp(m.shape.b, -kMaxMetricShear, kMaxMetricShear);
      // The bin is the quantized shape; samples within 1e-3 of the identity count as exactly it,
      // so an isotropic, orthogonal uv keeps exactly the identity.
      MetricShape q;
      q.a = std::exp2(step * std::round(std::log2(m.shape.a) / step));
      q.b = 0.5f * step * std::round(m.shape.b / (0.5f * step));
      const bool unitA = std::abs(std::log2(m.shape.a)) < 1e-3f;
      const bool unitB = std::abs(m.shape.b) < 1e-3f;
      auto it =
          std::find_if(ranges.begin(), ranges.end(), [&](const Range& r) { return r.bin == q; });
      if (it == ranges.end()) it = ranges.insert(ranges.end(), Range{q});
      lastRange = static_cast<size_t>(it - ranges.begin());
      lastLogA = unitA ? 0.0 : std::log2(static_cast<double>(m.shape.a));
      lastB = unitB ? 0.0 : static_cast<double>(m.shape.b);
    }
    Range& r = ranges[lastRange];
    r.logA += lastLogA;
    r.b += lastB;
    ++r.count;
    r.lo = std::min(r.lo, m.lengthPerU);
    r.hi = std::max(r.hi, m.lengthPerU);
  }
  std::vector<MetricClass> out;
  for (const Range& r : ranges) {
    const double logA = r.logA / r.count, b = r.b / r.count;
    MetricShape shape;
    shape.a = std::abs(logA) < 1e-3 ? 1.0f : static_cast<float>(std::exp2(logA));
    shape.b = std::abs(b) < 1e-3 ? 0.0f : static_cast<float>(b);
    for (float l : metricClasses(r.lo, r.hi, stepOctaves)) out.push_back({l, shape});
  }
  return out;
}

}  // namespace

std::vector<MetricClass> metricClassesFor(std::span<const MetricClass> samples, float stepOctaves,
                                          float* stepUsed) {
  float step = std::max(stepOctaves, 1e-3f);
  std::vector<MetricClass> out = binnedClasses(samples, step);
  // Too many classes: the same binning at twice the step, until they fit. With the shapes clamped,
  // a step of 256 octaves or more is one bin in a, at most three in b and at most two lengths per
  // bin for any finite length: 6 classes, reached within 18 doublings of any step from 1e-3 on.
  for (int k = 0; out.size() > kMaxMetricClasses && k < 20; ++k)
    out = binnedClasses(samples, step *= 2.0f);
  if (stepUsed) *stepUsed = step;
  return out;
}

std::vector<float> metricClasses(float lo, float hi, float stepOctaves) {
  if (!(lo > 0.0f) || !std::isfinite(lo) || !std::isfinite(hi) || hi < lo) return {1.0f};
  if (hi / lo < 1.001f) return {std::sqrt(lo * hi)};
  const double octaves = std::log2(static_cast<double>(hi) / lo);
  const int steps =
      std::max(1, static_cast<int>(std::ceil(octaves / std::max(stepOctaves, 1e-3f) - 1e-6)));
  std::vector<float> out;
  for (int k = 0; k <= steps; ++k)
    out.push_back(static_cast<float>(lo * std::exp2(octaves * k / steps)));
  return out;
}

}  // namespace meso
