// Monotone piecewise-linear CDFs over equal bins, and their exact inverses (used by
// redistribution).
#pragma once

#include <array>
#include <cstdint>
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

// A guide to one cumulative table's inverse (n + 1 edges): guide[g], g = 0 .. kCdfGuideSize, is the
// largest edge i < n with C(i) < g / kCdfGuideSize (0 when there is none), so the inverse at p in
// [g, g + 1] / kCdfGuideSize lies in bins guide[g] .. guide[g + 1]. With the guides of a mixture's
// tables, cdfInverse brackets its search instead of bisecting all edges (the pixel loop's
// redistribution does two inverses of up to eight tables per normal).
inline constexpr int kCdfGuideSize = 64;
void appendGuide(std::span<const float> cdf, std::vector<uint16_t>& out);

// The cosines of each bin's edges for BinShape::SolidAngle, bit for bit as the lookups would
// compute them (cos(lo + i width) and cos of that plus width), so that tables can skip two cosines
// a lookup.
struct BinCosines {
  BinCosines() = default;
  BinCosines(float lo, float width, size_t bins);
  std::vector<float> lower, upper;
};

// A mixture sum_k w_k C_k of up to eight cumulative tables of one length (weights >= 0, summing to
// 1): a monotone CDF again, so conditional maps can be interpolated between slices and bins.
struct CdfMix {
  std::array<std::span<const float>, 8> cdf{};
  std::array<float, 8> w{};
  std::array<const uint16_t*, 8> guide{};  // each table's guide (appendGuide), or null
  int count = 0;
  void add(std::span<const float> c, float weight, const uint16_t* g = nullptr) {
    if (!(weight > 0.0f) || count == 8) return;  // weights sum to 1: at least one is positive
    cdf[count] = c;
    guide[count] = g;
    w[count++] = weight;
  }
  float at(size_t i) const {
    float v = w[0] * cdf[0][i];
    for (int k = 1; k < count; ++k) v += w[k] * cdf[k][i];
    return count == 1 ? cdf[0][i] : v;
  }
  size_t edges() const { return cdf[0].size(); }
};

// `cosines` (optional, for SolidAngle bins) replaces the edge cosines; the result is the same.
// cdfInverse uses the mixture's guides when every table has one; the result is the same as without.
float cdfForward(const CdfMix& mix, float lo, float width, float x,
                 BinShape shape = BinShape::Uniform, const BinCosines* cosines = nullptr);
float cdfInverse(const CdfMix& mix, float lo, float width, float p,
                 BinShape shape = BinShape::Uniform, const BinCosines* cosines = nullptr);

}  // namespace meso
