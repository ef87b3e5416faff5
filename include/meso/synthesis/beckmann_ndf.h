// Beckmann & Spizzichino 1963 (as in Kautz et al. 2001, section 3.1): the Gaussian slope NDF,
// isotropic and anisotropic (Ward 1992 form).
#pragma once

#include "meso/synthesis/ndf.h"

namespace meso {

// D(m) = exp(-(m.x^2 / ax^2 + m.y^2 / ay^2) / m.z^2) / (pi ax ay m.z^4)
// i.e. the slopes (-m.x / m.z, -m.y / m.z) are Gaussian with standard deviations ax / sqrt(2) and
// ay / sqrt(2) along the frame's x and y axes (the principal frame). ax = ay is isotropic Beckmann.
// Evaluated in double precision so that alpha from 1e-6 to 1e6 and m.z -> 0 stay finite.
class BeckmannNdf : public Ndf {
 public:
  // Isotropic; alpha > 0 and finite, else meso::Error.
  explicit BeckmannNdf(float alpha);
  // Anisotropic, alpha along the principal x and y axes; both > 0 and finite, else meso::Error.
  BeckmannNdf(float alphaX, float alphaY);

  float D(const Vec3& m) const override;
  // Slopes up to 4.5 alpha per axis (6.4 standard deviations: a tail mass below 1e-9), as normal
  // components k / sqrt(1 + k^2), k = 4.5 alpha.
  Vec2 support() const override;
  std::string name() const override;
  uint64_t fingerprint() const override;

  float alphaX() const { return alphaX_; }
  float alphaY() const { return alphaY_; }

 private:
  float alphaX_, alphaY_;
};

}  // namespace meso
