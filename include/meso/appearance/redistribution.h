// Becker & Max 1993, section 3 and eq. (9); DESIGN.md section 4. R_theta = G_theta^-1 o F takes a
// bump normal to a normal distributed like the visible normals at view angle theta;
// R_theta^-1 = F^-1 o G_theta (the paper's q) goes back. Both are table lookups.
#pragma once

#include "meso/appearance/piecewise_cdf.h"
#include "meso/appearance/visible_normal_histogram.h"

#include <vector>

namespace meso {

enum class RedistributionVariant {
  Separable,    // theta_N and phi mapped by their marginals, independently (the paper's maps)
  Conditional,  // phi by its marginal first, then theta_N by its distribution at that phi,
                // interpolated linearly between phi-bin centres so the map is continuous
                // (meso's default: see TableSettings)
};

class Redistribution {
 public:
  Redistribution(const VisibleNormalHistogram& distr, RedistributionVariant variant);

  // R_theta(n): a bump normal to the visible-at-thetaV distribution. Slices are interpolated by
  // mixing their CDFs, so the map stays monotone and exactly invertible between slices.
  NormalAngles toVisible(float thetaV, NormalAngles n) const;
  // R_theta^-1(n).
  NormalAngles toBump(float thetaV, NormalAngles n) const;
  // Partial displacement: n' = R_thetaV(R_thetaW^-1(n)) with theta_W = arccot(cot(theta_V) / disp).
  // disp <= 0 is plain redistribution R_thetaV(n); disp >= 1 is the identity (full displacement).
  NormalAngles partial(float thetaV, float disp, NormalAngles n) const;

  RedistributionVariant variant() const { return variant_; }

 private:
  struct SlicePosition {
    int k0;
    int k1;
    float w;
  };
  SlicePosition locate(float thetaV) const;
  std::span<const float> thetaCdf(int k, int phiBin) const;
  std::span<const float> phiCdf(int k) const;
  int phiBinOf(float phi) const;
  // The theta_N CDF at azimuth phi of slice mix (k0, k1, w): the marginal (separable), or the
  // conditionals of the two phi bins whose centres bracket phi, mixed linearly (conditional).
  CdfMix thetaCdfAt(int k0, int k1, float w, float phi) const;

  VisibleNormalHistogram layout_;  // resolution and bin geometry (masses unused)
  RedistributionVariant variant_;
  // thetaCdfs_[k][c] for c = 0 (marginal) or 1 + phi bin (conditional): thetaN + 1 edges each.
  std::vector<float> thetaCdfs_;
  std::vector<float> phiCdfs_;  // phiCdfs_[k]: phi + 1 edges
  int thetaCdfsPerSlice_;
};

// theta_W = arccot(cot(theta_V) / disp), written as atan2(disp sin theta_V, cos theta_V) so that
// disp = 0 gives 0 and theta_V = pi/2 gives pi/2 without dividing by zero.
float thetaW(float thetaV, float disp);

}  // namespace meso
