// The axes of meso's angular tables (DESIGN.md section 4).
#include "meso/appearance/table_axis.h"

namespace meso {

TableAxis locateOnAxis(float x, float lo, float hi, int n) {
  float s = std::isfinite(x) ? (x - lo) / (hi - lo) * static_cast<float>(n - 1) : 0.0f;
  s = std::clamp(s, 0.0f, static_cast<float>(n - 1));
  const int i0 = std::min(static_cast<int>(s), std::max(n - 2, 0));
  return {i0, std::min(i0 + 1, n - 1), s - static_cast<float>(i0)};
}

TableAxis locateViewAzimuth(float phiV, int n) {
  if (n <= 1) return {};
  float s = (std::isfinite(phiV) ? phiV : 0.0f) / (2.0f * kPi) * static_cast<float>(n) - 0.5f;
  s -= static_cast<float>(n) * std::floor(s / static_cast<float>(n));
  const int m0 = std::min(static_cast<int>(s), n - 1);
  return {m0, (m0 + 1) % n, std::clamp(s - static_cast<float>(m0), 0.0f, 1.0f)};
}

float wrapAngle(float a) {
  if (!std::isfinite(a)) return 0.0f;
  a = std::fmod(a, 2.0f * kPi);
  if (a > kPi) a -= 2.0f * kPi;
  if (a < -kPi) a += 2.0f * kPi;
  return a;
}

}  // namespace meso
