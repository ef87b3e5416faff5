// Becker & Max 1993, section 3 and eq. (9); DESIGN.md section 4. R_theta = G_theta^-1 o F takes a
// bump normal to a normal distributed like the visible normals at view angle theta;
// R_theta^-1 = F^-1 o G_theta (the paper's q) goes back. Both are table lookups.
#pragma once

#include "meso/core/piecewise_cdf.h"
#include "meso/appearance/visible_normal_histogram.h"
#include "meso/scene/choices.h"  // RedistributionVariant

#include <array>
#include <vector>

namespace meso {

class Redistribution {
 public:
  Redistribution(const VisibleNormalHistogram& distr, RedistributionVariant variant);

  // R_theta(n): a bump normal to the visible-at-thetaV distribution. Slices are interpolated by
  // mixing their CDFs, so the map stays monotone and exactly invertible between slices.
  // phiV is the view's azimuth about the relief's own axes; it matters only for tables with view-
  // azimuth slices (HistogramResolution::phiV > 1), whose slices are mixed around it.
  NormalAngles toVisible(float thetaV, float phiV, NormalAngles n) const;
  NormalAngles toVisible(float thetaV, NormalAngles n) const { return toVisible(thetaV, 0.0f, n); }
  // R_theta^-1(n).
  NormalAngles toBump(float thetaV, float phiV, NormalAngles n) const;
  NormalAngles toBump(float thetaV, NormalAngles n) const { return toBump(thetaV, 0.0f, n); }
  // Partial displacement: n' = R_thetaV(R_thetaW^-1(n)) with theta_W = arccot(cot(theta_V) / disp).
  // disp <= 0 is plain redistribution R_thetaV(n); disp >= 1 is the identity (full displacement).
  NormalAngles partial(float thetaV, float phiV, float disp, NormalAngles n) const;
  NormalAngles partial(float thetaV, float disp, NormalAngles n) const {
    return partial(thetaV, 0.0f, disp, n);
  }

  RedistributionVariant variant() const { return variant_; }

 private:
  // The view slices around (theta_V, phi_V) and their weights (2 for isotropic tables, else 4).
  struct SliceMix {
    std::array<int, 4> slice{};
    std::array<float, 4> w{};
    int count = 0;
  };
  SliceMix locate(float thetaV, float phiV) const;
  CdfMix phiCdfAt(const SliceMix& m) const;
  // phi by the marginals, then theta_N by the (conditional) CDFs: from's distribution to to's.
  NormalAngles mapBetween(const SliceMix& from, const SliceMix& to, NormalAngles n) const;
  std::span<const float> thetaCdf(int k, int phiBin) const;
  std::span<const float> phiCdf(int k) const;
  // The theta_N CDF at azimuth phi of a slice mix: the marginal (separable), or the conditionals
  // of the two phi bins whose centres bracket phi, blended across their edge (conditional).
  CdfMix thetaCdfAt(const SliceMix& m, float phi) const;

  VisibleNormalHistogram layout_;  // resolution and bin geometry (masses unused)
  RedistributionVariant variant_;
  // thetaCdfs_[k][c] for c = 0 (marginal) or 1 + phi bin (conditional): thetaN + 1 edges each.
  std::vector<float> thetaCdfs_;
  std::vector<float> phiCdfs_;  // phiCdfs_[k]: phi + 1 edges
  int thetaCdfsPerSlice_;
  // Each CDF's inverse guide (kCdfGuideSize + 1 entries, in the CDFs' order) and the theta_N bins'
  // edge cosines: the same maps, without bisections and cosines in the pixel loop.
  std::vector<uint16_t> thetaGuides_, phiGuides_;
  BinCosines thetaCosines_;
  static void guidesOf(const std::vector<float>& cdfs, int edges, std::vector<uint16_t>& out);
  const uint16_t* thetaGuide(int k, int phiBin) const;
  const uint16_t* phiGuide(int k) const;
};

// theta_W = arccot(cot(theta_V) / disp), written as atan2(disp sin theta_V, cos theta_V) so that
// disp = 0 gives 0 and theta_V = pi/2 gives pi/2 without dividing by zero.
float thetaW(float thetaV, float disp);

}  // namespace meso
