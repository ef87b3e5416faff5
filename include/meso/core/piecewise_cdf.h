// Monotone piecewise-linear CDFs over equal bins, and their exact inverses: the one primitive of
// the redistribution maps (mixtures of tables, over angles), the synthesis lookup table L(r1, r2)
// (Kautz et al. 2001, section 4: M^-1 and C^-1) and the turbulence CDF G (two blended rows).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace meso {

// Cumulative masses at the n + 1 bin edges of [lo, lo + n * width], normalized so the last is 1.
// All-zero masses give the uniform CDF (so the maps stay defined for empty distributions).
// Negative masses count as 0. Sums are kept in double.
std::vector<float> cumulativeFromMasses(std::span<const float> masses);
// The same, appended to `out` (no temporary vectors: tables build thousands of them).
void appendCumulative(std::span<const float> masses, std::vector<float>& out);
void appendCumulative(std::span<const double> masses, std::vector<float>& out);

// ---- Tables in bin coordinates -------------------------------------------------------------
// A table of n + 1 edges C(0) .. C(n) is read at a position t in [0, n]: bin i = floor(t) (the
// last bin at t = n), fraction t - i inside it, F(t) = C(i) + (t - i) (C(i + 1) - C(i)). Callers
// map t to their own variable (a turbulence value, a normal's x or y) with their own arithmetic.

// How two rows a, b of CDF tables mix by w in [0, 1]. Equal in exact arithmetic, not in floats.
enum class RowMix {
  Weighted,  // (1 - w) a + w b, and exactly a at w = 0 (as CdfMix weights its tables)
  Lerp,      // a + w (b - a) (the turbulence CDF's blend of its octave-count rows)
};

// One CDF table, or two rows of them mixed by w (RowMix): a monotone CDF again.
struct CdfRows {
  std::span<const float> a, b;
  float w = 0.0f;
  RowMix mix = RowMix::Weighted;

  CdfRows() = default;
  explicit CdfRows(std::span<const float> row) : a(row), b(row) {}
  CdfRows(std::span<const float> rowA, std::span<const float> rowB, float weight, RowMix m)
      : a(rowA), b(rowB), w(weight), mix(m) {}
  float at(size_t i) const {
    if (mix == RowMix::Lerp) return a[i] + w * (b[i] - a[i]);
    return w == 0.0f ? a[i] : (1.0f - w) * a[i] + w * b[i];
  }
  size_t edges() const { return a.size(); }
};

// F(t): t clamped to [0, n] (NaN reads as 0), the result clamped to [0, 1]. Allocation-free.
float cdfForwardInBins(const CdfRows& rows, float t);

// Which inverse, where F is flat at p (a run of empty bins; p = 0 ahead of the support, p = 1
// beyond it):
enum class InverseSide {
  // The smallest t with F(t) = p: the largest edge i with C(i) < p, then linear inside bin i.
  // p <= C(0) gives the left end of the support (the first edge i with C(i + 1) > C(0)).
  Lower,
  // The largest t with F(t) = p: the largest edge i with C(i) <= p, then linear inside bin i.
  // p >= C(n) gives the right end of the support (the upper edge of the last bin with mass).
  Upper,
};

// An inverse's position: bin (one with mass, unless the table has none) and fraction in [0, 1].
struct BinPosition {
  size_t bin = 0;
  float fraction = 0.0f;
  float t() const { return static_cast<float>(bin) + fraction; }
};

// The inverse of cdfForwardInBins (p clamped to [0, 1], NaN reads as 0), by bisection over the
// edges: both sides land inside the support, so F(inverse(p)) = p for every p in [C(0), C(n)].
// Allocation-free.
BinPosition cdfInverseInBins(const CdfRows& rows, float p, InverseSide side);

// The position t in [0, n - 1] where a nondecreasing sequence at(0) .. at(n - 1), linear between
// its nodes, reaches v: the largest node i with at(i) < v, then linear; v <= at(0) gives 0 and
// v >= at(n - 1) gives n - 1. For sequences that are not CDFs (a lookup table's node values, as in
// NormalLookupTable::invert). Allocation-free.
template <class At>
float inverseNondecreasing(const At& at, int n, float v) {
  if (!(v > at(0))) return 0.0f;
  if (!(v < at(n - 1))) return static_cast<float>(n - 1);
  int lo = 0, hi = n - 1;
  while (hi - lo > 1) {  // invariant at(lo) < v <= at(hi)
    const int mid = (lo + hi) / 2;
    (at(mid) < v ? lo : hi) = mid;
  }
  const float w = at(hi) - at(lo);
  return static_cast<float>(lo) + (w > 0.0f ? (v - at(lo)) / w : 0.0f);
}

// ---- Tables over [lo, lo + n * width] --------------------------------------------------------

// How mass spreads inside a bin: evenly in x, or evenly in solid angle when x is a polar angle
// (uniform in cos x), which is right near the pole where the density per solid angle is smooth.
enum class BinShape { Uniform, SolidAngle };

// The CDF of one table or of two mixed rows (CdfRows) over bins of [lo, lo + n * width], evaluated
// at x; mass is spread inside each bin by `shape`. Allocation-free.
float cdfForward(const CdfRows& rows, float lo, float width, float x,
                 BinShape shape = BinShape::Uniform);

// The inverse of cdfForward: the smallest x with F(x) = p (p clamped to [0, 1]; p = 0 gives lo),
// by binary search over the edges and the bin shape's interpolation inside the bin.
// Allocation-free.
float cdfInverse(const CdfRows& rows, float lo, float width, float p,
                 BinShape shape = BinShape::Uniform);

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
