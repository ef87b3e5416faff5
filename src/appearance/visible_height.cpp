// The mean height of first hits on a relief level (visible_height.h).
#include "meso/appearance/visible_height.h"

#include "meso/appearance/material_tables.h"
#include "meso/core/rng.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace meso {

void buildVisibleHeights(MaterialRelief& relief, bool curvedSurface) {
  relief.visibleHeights.clear();
  // Levels ride on crests: the first on the limit surface's own (none on a plane), the others
  // also on the raised coarser levels' (ReliefDisplacement::crestCurvature).
  for (size_t i = 0; i < relief.levels.size(); ++i)
    relief.visibleHeights.emplace_back(
        relief.levels[i].partialSum ? *relief.levels[i].partialSum : relief.levels[i],
        i > 0 || curvedSurface);
}

float VisibleHeight::smithLambda(float a) {
  constexpr float kLargest = 1e6f;
  if (!(a > 0.0f)) return kLargest;
  const float lambda = 0.5f * (std::erf(a) - 1.0f) + std::exp(-a * a) / (2.0f * a * std::sqrt(kPi));
  return std::clamp(lambda, 0.0f, kLargest);
}

VisibleHeight::VisibleHeight(const ReliefLevel& level, bool crests) {
  // The points reliefSlopeRmsPerU uses.
  const std::vector<Vec2> points = levelSamplePoints(level);
  const int kPoints = static_cast<int>(points.size());
  std::vector<double> heights(points.size());
  double uu = 0.0, vv = 0.0, mean = 0.0;
  for (int k = 0; k < kPoints; ++k) {
    const Vec2 B = level.derivatives(points[k]);
    uu += static_cast<double>(B.x) * B.x;
    vv += static_cast<double>(B.y) * B.y;
    heights[k] = level.height(points[k]);
    mean += heights[k] / kPoints;
  }
  wavelength_ = level.wavelength();
  slopeRmsPerU_ = static_cast<float>(std::sqrt(std::max(uu, vv) / kPoints));
  std::sort(heights.begin(), heights.end());
  for (int j = 0; j < kNodes; ++j) {
    // The mean of the hit heights, whose distribution is C^(1 + Lambda), over the sorted samples.
    const double power = std::exp2(0.25 * j);  // 1 + Lambda
    double sum = 0.0, below = 0.0;
    for (int k = 0; k < kPoints; ++k) {
      const double at = std::pow(static_cast<double>(k + 1) / kPoints, power);
      sum += (heights[k] - mean) * (at - below);
      below = at;
    }
    table_[j] = std::isfinite(sum) ? static_cast<float>(sum) : 0.0f;
  }
  table_[0] = 0.0f;  // Lambda = 0: the heights' own mean, the mean plane (0 up to rounding)
  if (crests)
    buildCrestTable(level, heights.front(), heights.back(), mean);
  else
    crest_.fill(std::numeric_limits<float>::max());
}

// The crest's edge, marched through the relief itself (Smith's uncorrelated model underestimates
// it by 10-35% on fBm: the path across a crest is a few wavelengths, where heights are
// correlated). A horizontal ray at clearance c above the top of a crest of radius R (the unit-speed
// cylinder -x^2 / (2 R), the relief added vertically) is blocked exactly when c is below the
// highest point of base plus relief along it, so the edge moves out by the mean of that highest
// point (from the mean plane) over rays of random position and azimuth.
void VisibleHeight::buildCrestTable(const ReliefLevel& level, double lowest, double highest,
                                    double mean) {
  constexpr int kRays = 128;
  const float wavelength = level.wavelength();
  const float step = wavelength / 8.0f;
  const float range = static_cast<float>(highest - lowest);
  if (!(range > 0.0f) || !(wavelength > 0.0f) || !std::isfinite(range)) return;
  // Each node is its own march with its own seed: the same table for any thread count.
  tbb::parallel_for(0, kCrestNodes, [&](int j) {
    const float radius = wavelength / std::exp2(kCrestLog2Min + 0.5f * j);  // units of u
    // Beyond this the base has fallen below the lowest relief under the ray.
    const float steps = std::ceil(std::sqrt(2.0f * radius * range) / step);
    if (!(steps <= static_cast<float>(kMaxCrestSteps))) {
      // Relief very tall for its wavelength: such wide crests are left to the plane's value (the
      // smaller one is used), and the march stays bounded.
      crest_[j] = std::numeric_limits<float>::max();
      return;
    }
    Rng rng(0xc4e57 + j);
    double sum = 0.0;
    for (int r = 0; r < kRays; ++r) {
      const Vec2 at = Vec2(rng.uniform(), rng.uniform()) * 64.0f * wavelength;
      const float phi = 2.0f * kPi * rng.uniform();
      const Vec2 dir(std::cos(phi), std::sin(phi));
      float top = -std::numeric_limits<float>::infinity();
      for (int k = -static_cast<int>(steps); k <= static_cast<int>(steps); ++k) {
        const float x = static_cast<float>(k) * step;
        top = std::max(top, level.height(at + x * dir) - x * x / (2.0f * radius));
      }
      sum += (static_cast<double>(top) - mean) / kRays;
    }
    crest_[j] = std::isfinite(sum) ? static_cast<float>(sum) : 0.0f;
  });
}

// a = cot / (sqrt(2) sigma) with sigma the world rms slope; +infinity for zero relief.
float VisibleHeight::slopeA(float cot, float lengthPerU) const {
  const float sigma = slopeRmsPerU_ / lengthPerU;
  if (!(sigma > 0.0f)) return std::numeric_limits<float>::infinity();
  return cot / (std::sqrt(2.0f) * sigma);
}

namespace {

float cotOf(float cosTheta) {
  const float c = std::min(std::abs(cosTheta), 1.0f);
  const float s = std::sqrt(std::max(1.0f - c * c, 0.0f));
  return s > 0.0f ? c / s : std::numeric_limits<float>::infinity();
}

}  // namespace

bool VisibleHeight::grazing(float cosTheta, float lengthPerU) const {
  if (!(lengthPerU > 0.0f) || !std::isfinite(cosTheta)) return true;
  return slopeA(cotOf(cosTheta), lengthPerU) < 3.0f;
}

float VisibleHeight::at(float cosTheta, float lengthPerU, float curvature) const {
  if (!(slopeRmsPerU_ > 0.0f) || !(lengthPerU > 0.0f)) return 0.0f;
  const float a = slopeA(cotOf(std::isfinite(cosTheta) ? cosTheta : 0.0f), lengthPerU);
  const float x = std::clamp(4.0f * std::log2(1.0f + smithLambda(a)), 0.0f, kNodes - 1.0f);
  const int i = std::min(static_cast<int>(x), kNodes - 2);
  const float w = x - static_cast<float>(i);
  float h = table_[i] + w * (table_[i + 1] - table_[i]);
  if (curvature > 0.0f && std::isfinite(curvature)) {
    // A crest bounds the path through the relief as the view's angle does: the shorter one wins.
    // Curvature per unit of u (a unit-speed crest of radius R / lengthPerU^2) in wavelengths.
    const float k = curvature * lengthPerU * lengthPerU * wavelength_;
    const float y = std::clamp(2.0f * (std::log2(std::max(k, 1e-30f)) - kCrestLog2Min), 0.0f,
                               kCrestNodes - 1.0f);
    const int c = std::min(static_cast<int>(y), kCrestNodes - 2);
    const float v = y - static_cast<float>(c);
    h = std::min(h, v > 0.0f ? crest_[c] + v * (crest_[c + 1] - crest_[c]) : crest_[c]);
  }
  return std::isfinite(h) ? h : 0.0f;
}

}  // namespace meso
