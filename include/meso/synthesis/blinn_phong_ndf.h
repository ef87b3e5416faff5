// Blinn 1977 (as in Kautz et al. 2001, section 3.1): the cosine-power NDF.
#pragma once

#include "meso/synthesis/ndf.h"

namespace meso {

// D(m) = (n + 2) / (2 pi) * m.z^n: normalized so that integral D cos dw = 1 (the mass with
// cos(theta_m) < c is c^(n + 2)). Isotropic.
class BlinnPhongNdf : public Ndf {
 public:
  // exponent n >= 0 and finite, else meso::Error.
  explicit BlinnPhongNdf(float exponent);

  float D(const Vec3& m) const override;
  // sin(theta) where the remaining mass c^(n + 2) falls below 1e-8.
  Vec2 support() const override;
  std::string name() const override;
  uint64_t fingerprint() const override;

  float exponent() const { return exponent_; }

 private:
  float exponent_;
};

}  // namespace meso
