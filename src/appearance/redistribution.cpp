// Becker & Max 1993, section 3 (redistribution bump mapping) and section 4.1 (theta_W).
#include "meso/appearance/redistribution.h"

#include "meso/appearance/piecewise_cdf.h"
#include "meso/core/math.h"

#include <algorithm>
#include <cmath>

namespace meso {

// theta_N bins hold their mass evenly in solid angle ("solid-angle aware" bins).
constexpr BinShape kTheta = BinShape::SolidAngle;

float thetaW(float thetaV, float disp) {
  disp = std::clamp(std::isfinite(disp) ? disp : 0.0f, 0.0f, 1.0f);
  return std::atan2(disp * std::sin(thetaV), std::max(std::cos(thetaV), 0.0f));
}

Redistribution::Redistribution(const VisibleNormalHistogram& distr, RedistributionVariant variant)
    : layout_(distr.resolution(), distr.thetaVMax()), variant_(variant) {
  const HistogramResolution& r = distr.resolution();
  thetaCdfsPerSlice_ = variant == RedistributionVariant::Conditional ? 1 + r.phi : 1;
  std::vector<float> thetaMarginal(r.thetaN), phiMarginal(r.phi), column(r.thetaN);
  for (int k = 0; k < r.thetaV; ++k) {
    std::fill(thetaMarginal.begin(), thetaMarginal.end(), 0.0f);
    std::fill(phiMarginal.begin(), phiMarginal.end(), 0.0f);
    for (int i = 0; i < r.thetaN; ++i)
      for (int j = 0; j < r.phi; ++j) {
        thetaMarginal[i] += distr.mass(k, i, j);
        phiMarginal[j] += distr.mass(k, i, j);
      }
    const std::vector<float> tc = cumulativeFromMasses(thetaMarginal);
    thetaCdfs_.insert(thetaCdfs_.end(), tc.begin(), tc.end());
    for (int j = 0; variant == RedistributionVariant::Conditional && j < r.phi; ++j) {
      float total = 0.0f;
      for (int i = 0; i < r.thetaN; ++i) total += column[i] = distr.mass(k, i, j);
      // An empty phi bin borrows the marginal, so the conditional map is defined everywhere.
      const std::vector<float> cc = total > 1e-12f ? cumulativeFromMasses(column) : tc;
      thetaCdfs_.insert(thetaCdfs_.end(), cc.begin(), cc.end());
    }
    const std::vector<float> pc = cumulativeFromMasses(phiMarginal);
    phiCdfs_.insert(phiCdfs_.end(), pc.begin(), pc.end());
  }
}

Redistribution::SlicePosition Redistribution::locate(float thetaV) const {
  const int n = layout_.resolution().thetaV;
  float s = std::isfinite(thetaV) ? thetaV / layout_.thetaVMax() * static_cast<float>(n - 1) : 0.0f;
  s = std::clamp(s, 0.0f, static_cast<float>(n - 1));
  const int k0 = std::min(static_cast<int>(s), n - 2);
  return {k0, k0 + 1, s - static_cast<float>(k0)};
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

int Redistribution::phiBinOf(float phi) const { return layout_.phiBin(phi); }

CdfMix Redistribution::thetaCdfAt(int k0, int k1, float w, float phi) const {
  CdfMix mix;
  const int slices[2] = {k0, k1};
  const float sliceW[2] = {1.0f - w, w};
  if (variant_ == RedistributionVariant::Separable) {
    for (int a = 0; a < 2; ++a) mix.add(thetaCdf(slices[a], 0), sliceW[a]);
    return mix;
  }
  const int n = layout_.resolution().phi;
  // Position in bins from bin 0's centre; the two bins whose centres bracket phi are blended
  // linearly within kPhiBlend of a bin width around their common edge and each bin keeps its own
  // conditional elsewhere. The blend moves kPhiBlend / 8 of a bin's mass into each neighbour's
  // conditional (the chi-square tests of the joint still pass), and it must be wide because the phi
  // map is steep where few visible normals face away from the eye: half a bin keeps a 1e-3 degree
  // step of the input under 0.3 degrees of output (tests/appearance/redistribution_relief_test.cpp).
  constexpr float kPhiBlend = 0.5f;
  const float s = (wrapPi(phi) + kPi) / layout_.phiWidth() - 0.5f;
  const float base = std::floor(s);
  const float b = std::clamp((s - base - 0.5f) / kPhiBlend + 0.5f, 0.0f, 1.0f);
  const int j0 = ((static_cast<int>(base) % n) + n) % n, j1 = (j0 + 1) % n;
  for (int a = 0; a < 2; ++a) {
    mix.add(thetaCdf(slices[a], j0), sliceW[a] * (1.0f - b));
    mix.add(thetaCdf(slices[a], j1), sliceW[a] * b);
  }
  return mix;
}

NormalAngles Redistribution::toVisible(float thetaV, NormalAngles n) const {
  const SlicePosition s = locate(thetaV);
  const float tw = layout_.thetaNWidth(), pw = layout_.phiWidth();
  NormalAngles out;
  const float p = cdfForward(phiCdf(0), phiCdf(0), 0.0f, -kPi, pw, wrapPi(n.phi));
  out.phi = cdfInverse(phiCdf(s.k0), phiCdf(s.k1), s.w, -kPi, pw, p);
  const float q = cdfForward(thetaCdfAt(0, 0, 0.0f, n.phi), 0.0f, tw, n.thetaN, kTheta);
  out.thetaN = cdfInverse(thetaCdfAt(s.k0, s.k1, s.w, out.phi), 0.0f, tw, q, kTheta);
  return out;
}

NormalAngles Redistribution::toBump(float thetaV, NormalAngles n) const {
  const SlicePosition s = locate(thetaV);
  const float tw = layout_.thetaNWidth(), pw = layout_.phiWidth();
  NormalAngles out;
  const float p = cdfForward(phiCdf(s.k0), phiCdf(s.k1), s.w, -kPi, pw, wrapPi(n.phi));
  out.phi = cdfInverse(phiCdf(0), phiCdf(0), 0.0f, -kPi, pw, p);
  const float q = cdfForward(thetaCdfAt(s.k0, s.k1, s.w, n.phi), 0.0f, tw, n.thetaN, kTheta);
  out.thetaN = cdfInverse(thetaCdfAt(0, 0, 0.0f, out.phi), 0.0f, tw, q, kTheta);
  return out;
}

NormalAngles Redistribution::partial(float thetaV, float disp, NormalAngles n) const {
  if (!(disp > 0.0f)) return toVisible(thetaV, n);
  if (disp >= 1.0f) return n;
  return toVisible(thetaV, toBump(thetaW(thetaV, disp), n));
}

}  // namespace meso
