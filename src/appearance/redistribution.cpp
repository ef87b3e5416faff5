// Becker & Max 1993, section 3 (redistribution bump mapping) and section 4.1 (theta_W).
#include "meso/appearance/redistribution.h"

#include "meso/core/piecewise_cdf.h"
#include "meso/core/math.h"

#include <algorithm>
#include <cmath>

namespace meso {

// theta_N bins hold their mass evenly in solid angle ("solid-angle aware" bins).
constexpr BinShape kTheta = BinShape::SolidAngle;

float thetaW(float thetaV, float disp) {
  disp = std::clamp(std::isfinite(disp) ? disp : 0.0f, 0.0f, 1.0f);
  return fastAtan2(disp * std::sin(thetaV), std::max(std::cos(thetaV), 0.0f));
}

Redistribution::Redistribution(const VisibleNormalHistogram& distr, RedistributionVariant variant)
    : layout_(distr.resolution(), distr.thetaVMax(), VisibleNormalHistogram::LayoutOnly{}),
      variant_(variant) {
  const HistogramResolution& r = distr.resolution();
  thetaCdfsPerSlice_ = variant == RedistributionVariant::Conditional ? 1 + r.phi : 1;
  thetaCdfs_.reserve(static_cast<size_t>(distr.numSlices()) * thetaCdfsPerSlice_ * (r.thetaN + 1));
  phiCdfs_.reserve(static_cast<size_t>(distr.numSlices()) * (r.phi + 1));
  std::vector<float> thetaMarginal(r.thetaN), phiMarginal(r.phi), column(r.thetaN);
  for (int k = 0; k < distr.numSlices(); ++k) {
    std::fill(thetaMarginal.begin(), thetaMarginal.end(), 0.0f);
    std::fill(phiMarginal.begin(), phiMarginal.end(), 0.0f);
    for (int i = 0; i < r.thetaN; ++i)
      for (int j = 0; j < r.phi; ++j) {
        thetaMarginal[i] += distr.mass(k, i, j);
        phiMarginal[j] += distr.mass(k, i, j);
      }
    const size_t marginalAt = thetaCdfs_.size();
    appendCumulative(thetaMarginal, thetaCdfs_);
    for (int j = 0; variant == RedistributionVariant::Conditional && j < r.phi; ++j) {
      float total = 0.0f;
      for (int i = 0; i < r.thetaN; ++i) total += column[i] = distr.mass(k, i, j);
      // An empty phi bin borrows the marginal, so the conditional map is defined everywhere.
      if (total > 1e-12f)
        appendCumulative(column, thetaCdfs_);
      else
        thetaCdfs_.insert(
            thetaCdfs_.end(), thetaCdfs_.begin() + static_cast<std::ptrdiff_t>(marginalAt),
            thetaCdfs_.begin() + static_cast<std::ptrdiff_t>(marginalAt + r.thetaN + 1));
    }
    appendCumulative(phiMarginal, phiCdfs_);
  }
  guidesOf(thetaCdfs_, r.thetaN + 1, thetaGuides_);
  guidesOf(phiCdfs_, r.phi + 1, phiGuides_);
  thetaCosines_ = BinCosines(0.0f, layout_.thetaNWidth(), static_cast<size_t>(r.thetaN));
}

void Redistribution::guidesOf(const std::vector<float>& cdfs, int edges,
                              std::vector<uint16_t>& out) {
  const size_t len = static_cast<size_t>(edges);
  out.reserve(cdfs.size() / len * (kCdfGuideSize + 1));
  for (size_t at = 0; at + len <= cdfs.size(); at += len)
    appendGuide(std::span<const float>(cdfs.data() + at, len), out);
}

const uint16_t* Redistribution::thetaGuide(int k, int phiBin) const {
  const size_t c = variant_ == RedistributionVariant::Conditional ? 1 + phiBin : 0;
  return thetaGuides_.data() +
         (static_cast<size_t>(k) * thetaCdfsPerSlice_ + c) * (kCdfGuideSize + 1);
}

const uint16_t* Redistribution::phiGuide(int k) const {
  return phiGuides_.data() + static_cast<size_t>(k) * (kCdfGuideSize + 1);
}

Redistribution::SliceMix Redistribution::locate(float thetaV, float phiV) const {
  const HistogramResolution& r = layout_.resolution();
  const int n = r.thetaV;
  float t = std::isfinite(thetaV) ? thetaV / layout_.thetaVMax() * static_cast<float>(n - 1) : 0.0f;
  t = std::clamp(t, 0.0f, static_cast<float>(n - 1));
  const int k0 = std::min(static_cast<int>(t), n - 2);
  const float w = t - static_cast<float>(k0);
  SliceMix m;
  if (r.phiV == 1) {
    m.slice = {k0, k0 + 1, 0, 0};
    m.w = {1.0f - w, w, 0.0f, 0.0f};
    m.count = 2;
    return m;
  }
  // View azimuth: periodic, between the two slice centres around phiV.
  float s = (std::isfinite(phiV) ? phiV : 0.0f) / (2.0f * kPi) * static_cast<float>(r.phiV) - 0.5f;
  s -= static_cast<float>(r.phiV) * std::floor(s / static_cast<float>(r.phiV));
  const int a0 = std::min(static_cast<int>(s), r.phiV - 1), a1 = (a0 + 1) % r.phiV;
  const float b = std::clamp(s - static_cast<float>(a0), 0.0f, 1.0f);
  m.slice = {layout_.sliceOf(k0, a0), layout_.sliceOf(k0, a1), layout_.sliceOf(k0 + 1, a0),
             layout_.sliceOf(k0 + 1, a1)};
  m.w = {(1.0f - w) * (1.0f - b), (1.0f - w) * b, w * (1.0f - b), w * b};
  m.count = 4;
  return m;
}

CdfMix Redistribution::phiCdfAt(const SliceMix& m) const {
  CdfMix mix;
  for (int i = 0; i < m.count; ++i) mix.add(phiCdf(m.slice[i]), m.w[i], phiGuide(m.slice[i]));
  return mix;
}

std::span<const float> Redistribution::thetaCdf(int k, int phiBin) const {
  const size_t len = static_cast<size_t>(layout_.resolution().thetaN) + 1;
  const size_t c = variant_ == RedistributionVariant::Conditional ? 1 + phiBin : 0;
  return {thetaCdfs_.data() + (static_cast<size_t>(k) * thetaCdfsPerSlice_ + c) * len, len};
}

std::span<const float> Redistribution::phiCdf(int k) const {
  const size_t len = static_cast<size_t>(layout_.resolution().phi) + 1;
  return {phiCdfs_.data() + static_cast<size_t>(k) * len, len};
}

CdfMix Redistribution::thetaCdfAt(const SliceMix& m, float phi) const {
  CdfMix mix;
  if (variant_ == RedistributionVariant::Separable) {
    for (int i = 0; i < m.count; ++i)
      mix.add(thetaCdf(m.slice[i], 0), m.w[i], thetaGuide(m.slice[i], 0));
    return mix;
  }
  const int n = layout_.resolution().phi;
  // Position in bins from bin 0's centre; the two bins whose centres bracket phi are blended
  // linearly within kPhiBlend of a bin width around their common edge and each bin keeps its own
  // conditional elsewhere. The blend moves kPhiBlend / 8 of a bin's mass into each neighbour's
  // conditional (the chi-square tests of the joint still pass), and it must be wide because the phi
  // map is steep where few visible normals face away from the eye: half a bin keeps a 1e-3 degree
  // step of the input under 0.3 degrees of output
  // (tests/appearance/redistribution_relief_test.cpp).
  constexpr float kPhiBlend = 0.5f;
  const float s = (wrapPi(phi) + kPi) / layout_.phiWidth() - 0.5f;
  const float base = std::floor(s);
  const float b = std::clamp((s - base - 0.5f) / kPhiBlend + 0.5f, 0.0f, 1.0f);
  const int j0 = ((static_cast<int>(base) % n) + n) % n, j1 = (j0 + 1) % n;
  for (int i = 0; i < m.count; ++i) {
    mix.add(thetaCdf(m.slice[i], j0), m.w[i] * (1.0f - b), thetaGuide(m.slice[i], j0));
    mix.add(thetaCdf(m.slice[i], j1), m.w[i] * b, thetaGuide(m.slice[i], j1));
  }
  return mix;
}

NormalAngles Redistribution::mapBetween(const SliceMix& from, const SliceMix& to,
                                        NormalAngles n) const {
  const float tw = layout_.thetaNWidth(), pw = layout_.phiWidth();
  NormalAngles r;
  const float p = cdfForward(phiCdfAt(from), -kPi, pw, wrapPi(n.phi));
  r.phi = cdfInverse(phiCdfAt(to), -kPi, pw, p);
  const float q = cdfForward(thetaCdfAt(from, n.phi), 0.0f, tw, n.thetaN, kTheta, &thetaCosines_);
  r.thetaN = cdfInverse(thetaCdfAt(to, r.phi), 0.0f, tw, q, kTheta, &thetaCosines_);
  return r;
}

NormalAngles Redistribution::toVisible(float thetaV, float phiV, NormalAngles n) const {
  return mapBetween(locate(0.0f, phiV), locate(thetaV, phiV), n);
}

NormalAngles Redistribution::toBump(float thetaV, float phiV, NormalAngles n) const {
  return mapBetween(locate(thetaV, phiV), locate(0.0f, phiV), n);
}

NormalAngles Redistribution::partial(float thetaV, float phiV, float disp, NormalAngles n) const {
  if (!(disp > 0.0f)) return toVisible(thetaV, phiV, n);
  if (disp >= 1.0f) return n;
  // R_thetaV o R_thetaW^-1 = G_thetaV^-1 o F o F^-1 o G_thetaW, and F o F^-1 is the identity on
  // [0, 1] (the inverse lands inside the support): one map from theta_W's slices to theta_V's.
  return mapBetween(locate(thetaW(thetaV, disp), phiV), locate(thetaV, phiV), n);
}

}  // namespace meso
