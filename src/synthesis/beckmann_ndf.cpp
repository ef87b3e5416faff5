// Beckmann & Spizzichino 1963; anisotropic form of Ward 1992 (as used by Kautz et al. 2001).
#include "meso/synthesis/beckmann_ndf.h"

#include "meso/core/error.h"
#include "meso/core/hash.h"

#include <cmath>
#include <sstream>

namespace meso {
namespace {

float checkedAlpha(float a, const char* which) {
  if (!(a > 0.0f) || !std::isfinite(a)) {
    std::ostringstream s;
    s << "beckmann NDF: " << which << " must be positive and finite (got " << a << ")";
    throw Error(s.str());
  }
  return a;
}

float supportOf(float alpha) {
  const double k = 4.5 * static_cast<double>(alpha);
  return static_cast<float>(std::min(1.0, k / std::sqrt(1.0 + k * k)));
}

}  // namespace

BeckmannNdf::BeckmannNdf(float alpha) : BeckmannNdf(alpha, alpha) {}

BeckmannNdf::BeckmannNdf(float alphaX, float alphaY)
    : alphaX_(checkedAlpha(alphaX, "alpha x")), alphaY_(checkedAlpha(alphaY, "alpha y")) {}

float BeckmannNdf::D(const Vec3& m) const {
  if (!(m.z > 0.0f)) return 0.0f;
  const double ax = alphaX_, ay = alphaY_, mz2 = static_cast<double>(m.z) * m.z;
  const double mx = m.x, my = m.y;
  // tan^2(theta) (cos^2 phi / ax^2 + sin^2 phi / ay^2), written without trigonometry.
  const double e = (mx * mx / (ax * ax) + my * my / (ay * ay)) / mz2;
  if (!(e < 700.0)) return 0.0f;  // also catches e = NaN from m.z^2 underflowing to 0
  const double d = std::exp(-e) / (kPi * ax * ay * mz2 * mz2);
  return std::isfinite(d) ? static_cast<float>(std::min(d, 3.0e38)) : 0.0f;
}

Vec2 BeckmannNdf::support() const { return Vec2(supportOf(alphaX_), supportOf(alphaY_)); }

std::string BeckmannNdf::name() const {
  std::ostringstream s;
  s << "beckmann(" << alphaX_;
  if (alphaY_ != alphaX_) s << ", " << alphaY_;
  s << ")";
  return s.str();
}

uint64_t BeckmannNdf::fingerprint() const {
  return Hasher().string("BeckmannNdf/1").value(alphaX_).value(alphaY_).digest();
}

}  // namespace meso
