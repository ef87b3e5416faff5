#include "meso/core/piecewise_cdf.h"

#include "meso/core/check.h"
#include "meso/core/math.h"

#include <algorithm>
#include <cmath>

namespace meso {

std::vector<float> cumulativeFromMasses(std::span<const float> masses) {
  const size_t n = masses.size();
  std::vector<double> c(n + 1, 0.0);
  for (size_t i = 0; i < n; ++i) c[i + 1] = c[i] + std::max(0.0f, masses[i]);
  std::vector<float> out(n + 1);
  for (size_t i = 0; i <= n; ++i)
    out[i] = c[n] > 0.0 ? static_cast<float>(c[i] / c[n])
                        : static_cast<float>(i) / static_cast<float>(n);
  out[n] = 1.0f;
  return out;
}

namespace {

template <class Mass>
void appendCumulativeOf(std::span<const Mass> masses, std::vector<float>& out) {
  const size_t n = masses.size();
  double total = 0.0;
  for (Mass m : masses) total += std::max(Mass(0), m);
  double c = 0.0;
  out.push_back(0.0f);
  for (size_t i = 0; i < n; ++i) {
    c += std::max(Mass(0), masses[i]);
    out.push_back(i + 1 == n    ? 1.0f
                  : total > 0.0 ? static_cast<float>(c / total)
                                : static_cast<float>(i + 1) / static_cast<float>(n));
  }
}

}  // namespace

void appendCumulative(std::span<const float> masses, std::vector<float>& out) {
  appendCumulativeOf(masses, out);
}

void appendCumulative(std::span<const double> masses, std::vector<float>& out) {
  appendCumulativeOf(masses, out);
}

void appendGuide(std::span<const float> cdf, std::vector<uint16_t>& out) {
  MESO_DCHECK(cdf.size() >= 2, "a CDF of one bin or more");
  const size_t n = cdf.size() - 1;
  size_t i = 0;
  for (int g = 0; g <= kCdfGuideSize; ++g) {
    const float p = static_cast<float>(g) / static_cast<float>(kCdfGuideSize);
    while (i + 1 < n && cdf[i + 1] < p) ++i;
    out.push_back(static_cast<uint16_t>(i));
  }
}

BinCosines::BinCosines(float lo, float width, size_t bins) : lower(bins), upper(bins) {
  for (size_t i = 0; i < bins; ++i) {
    const float x0 = lo + static_cast<float>(i) * width;
    lower[i] = std::cos(x0);
    upper[i] = std::cos(x0 + width);
  }
}

namespace {

// The largest edge i in [lo, hi) with at(i) < p (or at(i) <= p when `inclusive`), by bisection: the
// bin of the inverse at p of a nondecreasing table, given at(lo) below p and at(hi) not.
template <class Table>
size_t bisectEdges(const Table& table, size_t lo, size_t hi, float p, bool inclusive) {
  MESO_DCHECK(lo < hi, "a nonempty range of edges");
  while (hi - lo > 1) {
    const size_t mid = (lo + hi) / 2;
    const float c = table.at(mid);
    if (inclusive ? c <= p : c < p)
      lo = mid;
    else
      hi = mid;
  }
  return lo;
}

// The fraction of bin i where the table's linear interpolation reaches p.
template <class Table>
float fractionAt(const Table& table, size_t i, float p) {
  const float c0 = table.at(i), c1 = table.at(i + 1);
  return c1 > c0 ? std::clamp((p - c0) / (c1 - c0), 0.0f, 1.0f) : 0.0f;
}

// Fraction of bin i below x, and its inverse, for the bin shape.
float fractionIn(size_t i, float lo, float width, float x, BinShape shape,
                 const BinCosines* cosines = nullptr) {
  const float x0 = lo + static_cast<float>(i) * width;
  if (shape == BinShape::Uniform) return (x - x0) / width;
  const float c0 = cosines ? cosines->lower[i] : std::cos(x0);
  const float c1 = cosines ? cosines->upper[i] : std::cos(x0 + width);
  return std::clamp((c0 - std::cos(x)) / (c0 - c1), 0.0f, 1.0f);
}

float positionIn(size_t i, float lo, float width, float f, BinShape shape,
                 const BinCosines* cosines = nullptr) {
  const float x0 = lo + static_cast<float>(i) * width;
  if (shape == BinShape::Uniform) return x0 + f * width;
  const float c0 = cosines ? cosines->lower[i] : std::cos(x0);
  const float c1 = cosines ? cosines->upper[i] : std::cos(x0 + width);
  return fastAcos(c0 - f * (c0 - c1));
}

// The largest edge i < n with mix(i) < p (0 when there is none): the bin of the inverse at p.
// With guides, a bracket from them, then a bisection inside it and a check of its ends (the
// mixture's weights sum to 1 only up to rounding, so the bracket is a guess that is verified);
// the answer is the same edge as a bisection over all edges, because the mixture is monotone.
size_t inverseBin(const CdfMix& mix, float p) {
  const size_t n = mix.edges() - 1;
  size_t loI = 0, hiI = n;
  bool guided = true;
  for (int k = 0; k < mix.count; ++k) guided = guided && mix.guide[k] != nullptr;
  if (guided) {
    const int g =
        std::min(static_cast<int>(p * static_cast<float>(kCdfGuideSize)), kCdfGuideSize - 1);
    loI = n, hiI = 0;
    for (int k = 0; k < mix.count; ++k) {
      loI = std::min<size_t>(loI, mix.guide[k][g]);
      hiI = std::max<size_t>(hiI, mix.guide[k][g + 1]);
    }
    hiI = std::min(hiI + 1, n);
    while (loI > 0 && !(mix.at(loI) < p)) --loI;  // verify the bracket's ends
    while (hiI < n && mix.at(hiI) < p) ++hiI;
  }
  return bisectEdges(mix, loI, hiI, p, false);
}

}  // namespace

float cdfForwardInBins(const CdfRows& rows, float t) {
  const size_t n = rows.edges() - 1;
  t = std::clamp(t == t ? t : 0.0f, 0.0f, static_cast<float>(n));
  const size_t i = std::min(static_cast<size_t>(t), n - 1);
  const float f = t - static_cast<float>(i);
  const float c0 = rows.at(i), c1 = rows.at(i + 1);
  return std::clamp(c0 + f * (c1 - c0), 0.0f, 1.0f);
}

BinPosition cdfInverseInBins(const CdfRows& rows, float p, InverseSide side) {
  const size_t n = rows.edges() - 1;
  p = std::clamp(p == p ? p : 0.0f, 0.0f, 1.0f);
  BinPosition r;
  if (side == InverseSide::Lower && !(p > rows.at(0))) {
    const float first = rows.at(0);  // the left end of the support
    while (r.bin < n && !(rows.at(r.bin + 1) > first)) ++r.bin;
    return r;
  }
  if (side == InverseSide::Upper && !(p < rows.at(n))) {
    r.bin = n - 1;  // the right end of the support
    while (r.bin > 0 && !(rows.at(r.bin + 1) > rows.at(r.bin))) --r.bin;
    r.fraction = 1.0f;
    return r;
  }
  r.bin = bisectEdges(rows, 0, n, p, side == InverseSide::Upper);
  r.fraction = fractionAt(rows, r.bin, p);
  return r;
}

float cdfForward(const CdfRows& rows, float lo, float width, float x, BinShape shape) {
  MESO_DCHECK(rows.edges() >= 2, "a CDF of one bin or more");
  MESO_DCHECK(width > 0.0f && std::isfinite(width) && std::isfinite(lo), "finite bins");
  const size_t n = rows.edges() - 1;
  const float t = (x - lo) / width;
  if (!(t > 0.0f)) return 0.0f;  // also catches NaN
  if (t >= static_cast<float>(n)) return 1.0f;
  const size_t i = std::min(static_cast<size_t>(t), n - 1);
  const float f = fractionIn(i, lo, width, x, shape);
  const float c0 = rows.at(i), c1 = rows.at(i + 1);
  return c0 + f * (c1 - c0);
}

float cdfInverse(const CdfRows& rows, float lo, float width, float p, BinShape shape) {
  MESO_DCHECK(rows.edges() >= 2, "a CDF of one bin or more");
  MESO_DCHECK(width > 0.0f && std::isfinite(width) && std::isfinite(lo), "finite bins");
  const size_t n = rows.edges() - 1;
  p = std::clamp(std::isfinite(p) ? p : 0.0f, 0.0f, 1.0f);
  // Largest edge i with C(i) < p (first edge where the CDF reaches p is i + 1), so zero-mass bins
  // before the answer are skipped.
  const size_t i = bisectEdges(rows, 0, n, p, false);
  return positionIn(i, lo, width, fractionAt(rows, i, p), shape);
}

float cdfForward(const CdfMix& mix, float lo, float width, float x, BinShape shape,
                 const BinCosines* cosines) {
  const size_t n = mix.edges() - 1;
  const float t = (x - lo) / width;
  if (!(t > 0.0f)) return 0.0f;
  if (t >= static_cast<float>(n)) return 1.0f;
  const size_t i = std::min(static_cast<size_t>(t), n - 1);
  const float f = fractionIn(i, lo, width, x, shape, cosines);
  const float c0 = mix.at(i), c1 = mix.at(i + 1);
  const float c = c0 + f * (c1 - c0);
  // At the top edge of the support the mixture sums to 1 only up to rounding; snap, so that a
  // normal beyond the support and one on its edge both map to the inverse's top (which may lie
  // past a run of empty bins).
  return c > 1.0f - 1e-6f ? 1.0f : c;
}

float cdfInverse(const CdfMix& mix, float lo, float width, float p, BinShape shape,
                 const BinCosines* cosines) {
  // The top 1e-6 of mass is left out: a stray bin far in the tail, mixed in by a tiny slice weight,
  // would otherwise decide where every normal at p = 1 goes (by float rounding of that weight).
  p = std::clamp(std::isfinite(p) ? p : 0.0f, 0.0f, 1.0f - 1e-6f);
  const size_t i = inverseBin(mix, p);
  return positionIn(i, lo, width, fractionAt(mix, i, p), shape, cosines);
}

}  // namespace meso
