// Kautz et al. 2001, section 7: an NDF for an existing bump map (slope covariance -> anisotropic
// Beckmann, or a normal histogram -> tabulated NDF).
#include "meso/synthesis/ndf_estimate.h"

#include "meso/core/error.h"
#include "meso/synthesis/beckmann_ndf.h"
#include "meso/synthesis/tabulated_ndf.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace meso {

NdfEstimate estimateNdf(const HeightSource& source, const NdfEstimateOptions& options) {
  const int n = options.samples;
  if (n < 2 || n > 16384 || !std::isfinite(options.slopeScale) || options.tableResolution < 2 ||
      options.tableResolution > 4096)
    throw Error(
        "NDF estimate: need 2..16384 samples per axis, a finite slope scale and 2..4096 table "
        "cells (got " +
        std::to_string(n) + ", " + std::to_string(options.slopeScale) + ", " +
        std::to_string(options.tableResolution) + ")");
  NdfEstimate e;
  const int res = options.tableResolution;
  std::vector<float> counts(
      options.model == NdfModel::Tabulated ? static_cast<size_t>(res) * res : 0, 0.0f);
  double a = 0.0, b = 0.0, c = 0.0;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const Vec2 s = options.slopeScale * source.gradient(Vec2((i + 0.5f) / n, (j + 0.5f) / n));
      if (!std::isfinite(s.x) || !std::isfinite(s.y)) continue;
      a += static_cast<double>(s.x) * s.x, b += static_cast<double>(s.x) * s.y,
          c += static_cast<double>(s.y) * s.y;
      if (counts.empty()) continue;
      const Vec3 m = glm::normalize(Vec3(-s.x, -s.y, 1.0f));
      const int ci = std::clamp(static_cast<int>((m.x + 1.0f) * 0.5f * res), 0, res - 1);
      const int cj = std::clamp(static_cast<int>((m.y + 1.0f) * 0.5f * res), 0, res - 1);
      counts[static_cast<size_t>(cj) * res + ci] += 1.0f;
    }
  }
  const double count = static_cast<double>(n) * n;
  e.covariance = {static_cast<float>(a / count), static_cast<float>(b / count),
                  static_cast<float>(c / count)};
  if (options.model == NdfModel::Tabulated) {
    e.ndf = std::make_unique<TabulatedNdf>(res, res, std::move(counts));
    return e;
  }
  // Eigen-decomposition of the symmetric 2x2 K.
  const double ka = a / count, kb = b / count, kc = c / count;
  const double mean = 0.5 * (ka + kc), diff = 0.5 * (ka - kc),
               radius = std::sqrt(diff * diff + kb * kb);
  const double l1 = mean + radius, l2 = std::max(0.0, mean - radius);
  double angle = 0.5 * std::atan2(2.0 * kb, ka - kc);
  if (angle <= -0.5 * kPi) angle += kPi;
  e.principalAngle = static_cast<float>(angle);
  const auto alpha = [](double l) {
    return static_cast<float>(std::max(1e-4, std::sqrt(2.0 * std::max(l, 0.0))));
  };
  e.ndf = std::make_unique<BeckmannNdf>(alpha(l1), alpha(l2));
  return e;
}

Vec3 ndfTangent(const Vec3& N, const Vec3& T, float principalAngle) {
  Vec3 t = T - N * glm::dot(N, T);
  const float len = glm::length(t);
  if (!(len > 1e-6f)) return T;
  t /= len;
  const Vec3 b = glm::cross(N, t);
  return std::cos(principalAngle) * t + std::sin(principalAngle) * b;
}

}  // namespace meso
