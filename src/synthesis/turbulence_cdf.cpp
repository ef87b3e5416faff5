// Kautz et al. 2001, section 4: r' = G(r), G the CDF of the turbulence density g, computed
// numerically.
#include "meso/synthesis/turbulence_cdf.h"

#include "meso/core/error.h"
#include "meso/core/piecewise_cdf.h"
#include "meso/core/rng.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <string>

namespace meso {

namespace {

constexpr int kQuantiles = 2049;

// The probability of quantile k: crowded towards 0 and 1 (as NormalLookupTable::warp), where the
// tails of the turbulence feed the tails of the NDF.
inline float quantileLevel(float s) {
  return s < 0.5f ? 4.0f * s * s * s : 1.0f - 4.0f * (1.0f - s) * (1.0f - s) * (1.0f - s);
}

// Quantiles q[k] = F^-1(quantileLevel(k / (kQuantiles - 1))) of a piecewise-linear CDF over bins
// of [-range, range] (q[0]: the left end of the support).
void quantilesOf(std::span<const float> cdf, int bins, float range, float* q) {
  for (int k = 0; k < kQuantiles; ++k) {
    const float u = quantileLevel(static_cast<float>(k) / (kQuantiles - 1));
    q[k] =
        -range + cdfInverseInBins(CdfRows(cdf), u, InverseSide::Lower).t() * (2.0f * range / bins);
  }
}

// The piecewise-linear CDF over bins of [-range, range] of a distribution given by its quantiles.
void cdfOf(const float* q, int bins, float range, float* cdf) {
  int k = 0;
  for (int e = 0; e <= bins; ++e) {
    const float t = -range + e * (2.0f * range / bins);
    while (k < kQuantiles - 1 && !(q[k + 1] > t)) ++k;  // q[k] <= t < q[k + 1]
    float u;
    if (t < q[0]) {
      u = 0.0f;
    } else if (k >= kQuantiles - 1) {
      u = 1.0f;
    } else {
      // Linear in u between neighbouring quantiles.
      const float w = q[k + 1] - q[k], f = w > 0.0f ? (t - q[k]) / w : 1.0f;
      const float u0 = quantileLevel(static_cast<float>(k) / (kQuantiles - 1));
      const float u1 = quantileLevel(static_cast<float>(k + 1) / (kQuantiles - 1));
      u = u0 + f * (u1 - u0);
    }
    cdf[e] = std::clamp(u, 0.0f, 1.0f);
  }
  cdf[bins] = 1.0f;
}

// The coordinate in which the shape of t's distribution changes about linearly: the fading
// octave's normalized share enters t's shape at second order in its weight w_o(c).
inline float shapeCoordinate(float c) {
  const float k = std::floor(c), w = Turbulence::octaveWeight(c, static_cast<int>(k));
  return k + w * w;
}

}  // namespace

TurbulenceCdf::TurbulenceCdf(const Turbulence& turbulence, const TurbulenceCdfOptions& options)
    : bins_(options.bins), range_(turbulence.maxAbs()) {
  if (options.points < 16 || options.bins < 8 || options.bins > (1 << 20) ||
      !(options.domain > 0.0f))
    throw Error(
        "turbulence CDF: need at least 16 points, 8..2^20 bins and a positive domain (got " +
        std::to_string(options.points) + ", " + std::to_string(options.bins) + ")");
  const size_t measured = kMeasuredCounts.size();
  std::vector<float> quantiles(measured * kQuantiles), cdf;
  std::vector<double> counts(bins_);
  const double scale = bins_ / (2.0 * range_);
  for (size_t r = 0; r < measured; ++r) {
    std::fill(counts.begin(), counts.end(), 0.0);
    Rng rng(options.seed, r);
    const auto add = [&](float t) {
      counts[std::clamp(static_cast<int>((t + range_) * scale), 0, bins_ - 1)] += 1.0;
    };
    for (int k = 0; k < options.points; ++k) {
      const Vec2 p(options.domain * rng.uniform(), options.domain * rng.uniform());
      const Vec2 t = turbulence.evaluate(p, kMeasuredCounts[r]);
      add(t.x), add(-t.x), add(t.y), add(-t.y);
    }
    cdf.clear();
    appendCumulative(std::span<const double>(counts), cdf);
    quantilesOf(cdf, bins_, range_, &quantiles[r * kQuantiles]);
  }
  // Fine rows by displacement interpolation between the measured rows.
  const float first = kMeasuredCounts.front(), last = kMeasuredCounts.back();
  rowCount_ = static_cast<int>(std::lround((last - first) * kRowsPerOctave)) + 1;
  cdf_.assign(static_cast<size_t>(rowCount_) * (bins_ + 1), 0.0f);
  std::vector<float> q(kQuantiles);
  for (int f = 0; f < rowCount_; ++f) {
    const float c = first + static_cast<float>(f) / kRowsPerOctave;
    size_t a = 0;
    while (a + 2 < measured && !(c < kMeasuredCounts[a + 1])) ++a;
    const float sa = shapeCoordinate(kMeasuredCounts[a]),
                sb = shapeCoordinate(kMeasuredCounts[a + 1]);
    const float w = std::clamp((shapeCoordinate(c) - sa) / (sb - sa), 0.0f, 1.0f);
    for (int k = 0; k < kQuantiles; ++k)
      q[k] = quantiles[a * kQuantiles + k] +
             w * (quantiles[(a + 1) * kQuantiles + k] - quantiles[a * kQuantiles + k]);
    cdfOf(q.data(), bins_, range_, &cdf_[static_cast<size_t>(f) * (bins_ + 1)]);
  }
}

CdfRows TurbulenceCdf::blended(float c) const {
  const float x = (c - kMeasuredCounts.front()) * kRowsPerOctave;
  int row = 0;  // x <= 0 (and NaN): the first row
  float w = 0.0f;
  if (x > 0.0f && !(x < static_cast<float>(rowCount_ - 1))) {
    row = rowCount_ - 2, w = 1.0f;
  } else if (x > 0.0f) {
    row = static_cast<int>(x);
    w = x - static_cast<float>(row);
  }
  const size_t edges = static_cast<size_t>(bins_) + 1;
  const std::span<const float> a(&cdf_[static_cast<size_t>(row) * edges], edges);
  return CdfRows(a, std::span<const float>(a.data() + edges, edges), w, RowMix::Lerp);
}

float TurbulenceCdf::G(float t, float c) const {
  if (!(t == t)) t = 0.0f;  // NaN: the median
  const float x =
      std::clamp((t + range_) * (bins_ / (2.0f * range_)), 0.0f, static_cast<float>(bins_));
  return cdfForwardInBins(blended(c), x);
}

float TurbulenceCdf::inverse(float u, float c) const {
  u = std::clamp(u == u ? u : 0.5f, 0.0f, 1.0f);
  // u = 0 gives the left end of the support.
  return -range_ +
         cdfInverseInBins(blended(c), u, InverseSide::Lower).t() * (2.0f * range_ / bins_);
}

}  // namespace meso
