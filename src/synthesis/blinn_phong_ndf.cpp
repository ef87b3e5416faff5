// Blinn 1977: D(m) = (n + 2) / (2 pi) cos^n(theta_m), normalized by projected area.
#include "meso/synthesis/blinn_phong_ndf.h"

#include "meso/core/error.h"
#include "meso/core/hash.h"

#include <cmath>
#include <sstream>

namespace meso {

BlinnPhongNdf::BlinnPhongNdf(float exponent) : exponent_(exponent) {
  if (!(exponent >= 0.0f) || !std::isfinite(exponent)) {
    std::ostringstream s;
    s << "blinn-phong NDF: exponent must be >= 0 and finite (got " << exponent << ")";
    throw Error(s.str());
  }
}

float BlinnPhongNdf::D(const Vec3& m) const {
  if (!(m.z > 0.0f)) return 0.0f;
  const double n = exponent_;
  const double d = (n + 2.0) / (2.0 * kPi) * std::pow(std::min(static_cast<double>(m.z), 1.0), n);
  return std::isfinite(d) ? static_cast<float>(std::min(d, 3.0e38)) : 0.0f;
}

Vec2 BlinnPhongNdf::support() const {
  // Mass with cos(theta) < c is c^(n + 2); solve c^(n + 2) = 1e-8 for the cone's sin(theta).
  const double c = std::exp(std::log(1e-8) / (static_cast<double>(exponent_) + 2.0));
  return Vec2(static_cast<float>(std::sqrt(std::max(0.0, 1.0 - c * c))));
}

std::string BlinnPhongNdf::name() const {
  std::ostringstream s;
  s << "blinn-phong(" << exponent_ << ")";
  return s.str();
}

uint64_t BlinnPhongNdf::fingerprint() const {
  return Hasher().string("BlinnPhongNdf/1").value(exponent_).digest();
}

}  // namespace meso
