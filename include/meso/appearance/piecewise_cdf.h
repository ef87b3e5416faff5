// Monotone piecewise-linear CDFs over equal bins, and their exact inverses (used by
// redistribution).
#pragma once

#include <array>
#include <span>
#include <vector>

namespace meso {

// Cumulative masses at the n + 1 bin edges of [lo, lo + n * width], normalized so the last is 1.
// All-zero masses give the uniform CDF (so the maps stay defined for empty distributions).
std::vector<float> cumulativeFromMasses(std::span<const float> masses);
// The same, appended to `out` (no temporary vectors: tables build thousands of them).
void appendCumulative(std::span<const float> masses, std::vector<float>& out);

// How mass spreads inside a bin: evenly in x, or evenly in solid angle when x is a polar angle
// (uniform in cos x), which is right near the pole where the density per solid angle is smooth.
enum class BinShape { Uniform, SolidAngle };

// The CDF of a mixture (1 - w) * A + w * B of two cumulative tables (w in [0, 1]), evaluated at x;
// mass is spread evenly inside each bin. Allocation-free.
float cdfForward(std::span<const float> a, std::span<const float> b, float w, float lo, float width,
                 float x, BinShape shape = BinShape::Uniform);

// The inverse of cdfForward: the smallest x with F(x) = p (p clamped to [0, 1]), by binary search
// over the edges and linear interpolation inside the bin. Allocation-free.
float cdfInverse(std::span<const float> a, std::span<const float> b, float w, float lo, float width,
                 float p, BinShape shape = BinShape::Uniform);

// A mixture sum_k w_k C_k of up to eight cumulative tables of one length (weights >= 0, summing to
// 1): a monotone CDF again, so conditional maps can be interpolated between slices and bins.
struct CdfMix {
  std::array<std::span<const float>, 8> cdf{};
  std::array<float, 8> w{};
  int count = 0;
  void add(std::span<const float> c, float weight) {
    if (!(weight > 0.0f) || count == 8) return;  // weights sum to 1: at least one is positive
    cdf[count] = c;
    w[count++] = weight;
  }
  float at(size_t i) const {
    float v = w[0] * cdf[0][i];
    for (int k = 1; k < count; ++k) v += w[k] * cdf[k][i];
    return count == 1 ? cdf[0][i] : v;
  }
  size_t edges() const { return cdf[0].size(); }
};

float cdfForward(const CdfMix& mix, float lo, float width, float x,
                 BinShape shape = BinShape::Uniform);
float cdfInverse(const CdfMix& mix, float lo, float width, float p,
                 BinShape shape = BinShape::Uniform);

}  // namespace meso
