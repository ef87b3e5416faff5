// The mean height of first hits on a relief level (visible_height.h).
#include "meso/render/visible_height.h"

#include "meso/core/rng.h"
#include "meso/relief/height_table.h"
#include "meso/render/relief_levels.h"

#include <algorithm>
#include <cmath>

namespace meso {

float VisibleHeight::smithLambda(float a) {
  constexpr float kLargest = 1e6f;
  if (!(a > 0.0f)) return kLargest;
  const float lambda = 0.5f * (std::erf(a) - 1.0f) + std::exp(-a * a) / (2.0f * a * std::sqrt(kPi));
  return std::clamp(lambda, 0.0f, kLargest);
}

VisibleHeight::VisibleHeight(const ReliefLevel& level) {
  // The points reliefSlopeRmsPerU uses: 64 shortest wavelengths, or one period of a height table.
  const bool table = dynamic_cast<const HeightTable*>(level.source.get()) != nullptr;
  const float span = table && level.scale > 0.0f ? 1.0f / level.scale : 64.0f * level.wavelength();
  constexpr int kPoints = 1024;
  std::vector<double> heights(kPoints);
  Rng rng(0x51073);
  double uu = 0.0, vv = 0.0, mean = 0.0;
  for (int k = 0; k < kPoints; ++k) {
    const Vec2 uv = Vec2(rng.uniform(), rng.uniform()) * span;
    const Vec2 B = level.derivatives(uv);
    uu += static_cast<double>(B.x) * B.x;
    vv += static_cast<double>(B.y) * B.y;
    heights[k] = level.height(uv);
    mean += heights[k] / kPoints;
  }
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
}

float VisibleHeight::at(float cosTheta, float lengthPerU) const {
  if (!(slopeRmsPerU_ > 0.0f) || !(lengthPerU > 0.0f)) return 0.0f;
  const float c = std::min(std::abs(cosTheta), 1.0f);
  const float s = std::sqrt(std::max(1.0f - c * c, 0.0f));
  const float sigma = slopeRmsPerU_ / lengthPerU;
  const float a = s > 0.0f ? c / (s * std::sqrt(2.0f) * sigma) : 1e6f;
  const float x = std::clamp(4.0f * std::log2(1.0f + smithLambda(a)), 0.0f, kNodes - 1.0f);
  const int i = std::min(static_cast<int>(x), kNodes - 2);
  const float w = x - static_cast<float>(i);
  const float h = table_[i] + w * (table_[i + 1] - table_[i]);
  return std::isfinite(h) ? h : 0.0f;
}

}  // namespace meso
