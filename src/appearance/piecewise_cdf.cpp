#include "meso/appearance/piecewise_cdf.h"

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

void appendCumulative(std::span<const float> masses, std::vector<float>& out) {
  const size_t n = masses.size();
  double total = 0.0;
  for (float m : masses) total += std::max(0.0f, m);
  double c = 0.0;
  out.push_back(0.0f);
  for (size_t i = 0; i < n; ++i) {
    c += std::max(0.0f, masses[i]);
    out.push_back(i + 1 == n    ? 1.0f
                  : total > 0.0 ? static_cast<float>(c / total)
                                : static_cast<float>(i + 1) / static_cast<float>(n));
  }
}

void appendGuide(std::span<const float> cdf, std::vector<uint16_t>& out) {
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

inline float mixAt(std::span<const float> a, std::span<const float> b, float w, size_t i) {
  return w == 0.0f ? a[i] : (1.0f - w) * a[i] + w * b[i];
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
  return std::acos(std::clamp(c0 - f * (c0 - c1), -1.0f, 1.0f));
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
  while (hiI - loI > 1) {
    const size_t mid = (loI + hiI) / 2;
    if (mix.at(mid) < p)
      loI = mid;
    else
      hiI = mid;
  }
  return loI;
}

}  // namespace

float cdfForward(std::span<const float> a, std::span<const float> b, float w, float lo, float width,
                 float x, BinShape shape) {
  const size_t n = a.size() - 1;
  const float t = (x - lo) / width;
  if (!(t > 0.0f)) return 0.0f;  // also catches NaN
  if (t >= static_cast<float>(n)) return 1.0f;
  const size_t i = std::min(static_cast<size_t>(t), n - 1);
  const float f = fractionIn(i, lo, width, x, shape);
  const float c0 = mixAt(a, b, w, i), c1 = mixAt(a, b, w, i + 1);
  return c0 + f * (c1 - c0);
}

float cdfInverse(std::span<const float> a, std::span<const float> b, float w, float lo, float width,
                 float p, BinShape shape) {
  const size_t n = a.size() - 1;
  p = std::clamp(std::isfinite(p) ? p : 0.0f, 0.0f, 1.0f);
  // Largest edge i with C(i) < p (first edge where the CDF reaches p is i + 1), so zero-mass bins
  // before the answer are skipped.
  size_t loI = 0, hiI = n;
  while (hiI - loI > 1) {
    const size_t mid = (loI + hiI) / 2;
    if (mixAt(a, b, w, mid) < p)
      loI = mid;
    else
      hiI = mid;
  }
  const float c0 = mixAt(a, b, w, loI), c1 = mixAt(a, b, w, loI + 1);
  const float f = c1 > c0 ? std::clamp((p - c0) / (c1 - c0), 0.0f, 1.0f) : 0.0f;
  return positionIn(loI, lo, width, f, shape);
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
  const size_t loI = inverseBin(mix, p);
  const float c0 = mix.at(loI), c1 = mix.at(loI + 1);
  const float f = c1 > c0 ? std::clamp((p - c0) / (c1 - c0), 0.0f, 1.0f) : 0.0f;
  return positionIn(loI, lo, width, f, shape, cosines);
}

}  // namespace meso
