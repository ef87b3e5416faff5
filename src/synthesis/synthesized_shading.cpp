// Kautz et al. 2001, section 5.1: h -> h_m in the microfacet's tangent frame, then p(h_m).
#include "meso/synthesis/synthesized_shading.h"

#include <algorithm>
#include <cmath>

namespace meso {
namespace {

// A unit tangent orthogonal to N, from T (Gram-Schmidt) or, when T is degenerate, any one.
Vec3 tangentOf(const Vec3& N, const Vec3& T) {
  Vec3 t = T - N * glm::dot(N, T);
  const float len2 = glm::dot(t, t);
  if (len2 > 1e-12f && std::isfinite(len2)) return t * (1.0f / std::sqrt(len2));
  // Duff et al. 2017's branchless orthonormal basis.
  const float sign = std::copysign(1.0f, N.z), a = -1.0f / (sign + N.z), b = N.x * N.y * a;
  return Vec3(1.0f + sign * N.x * N.x * a, sign * b, -sign * N.x);
}

}  // namespace

Vec3 toMicrofacetFrame(const Vec3& m, const Vec3& h) {
  // R = I + [v]x + [v]x^2 / (1 + m.z), v = z x m: R x = (1 - mx^2 k, -mx my k, -mx) and so on.
  const float k = 1.0f / (1.0f + std::max(m.z, 0.0f));
  const Vec3 rx(1.0f - m.x * m.x * k, -m.x * m.y * k, -m.x);
  const Vec3 ry(-m.x * m.y * k, 1.0f - m.y * m.y * k, -m.y);
  return Vec3(glm::dot(h, rx), glm::dot(h, ry), glm::dot(h, m));
}

Vec3 ndfFrameToWorld(const Vec3& N, const Vec3& T, const Vec3& m) {
  const Vec3 t = tangentOf(N, T), b = glm::cross(N, t);
  return m.x * t + m.y * b + m.z * N;
}

Vec3 worldToNdfFrame(const Vec3& N, const Vec3& T, const Vec3& w) {
  const Vec3 t = tangentOf(N, T), b = glm::cross(N, t);
  return Vec3(glm::dot(w, t), glm::dot(w, b), glm::dot(w, N));
}

SynthesizedShading shadeSynthesized(const Ndf& ndf, const Vec3& N, const Vec3& T, const Vec3& V,
                                    const Vec3& L, const Vec3& m) {
  SynthesizedShading s;
  const float nv = glm::dot(N, V), nl = glm::dot(N, L);
  if (!(nv > 0.0f) || !(nl > 0.0f)) return s;
  const Vec3 mWorld = ndfFrameToWorld(N, T, m);
  s.diffuse = std::clamp(glm::dot(L, mWorld), 0.0f, 1.0f);
  const Vec3 sum = V + L;
  const float len2 = glm::dot(sum, sum);
  if (!(len2 > 1e-12f) || !std::isfinite(len2)) return s;
  const Vec3 hLocal = worldToNdfFrame(N, T, sum * (1.0f / std::sqrt(len2)));
  Vec3 hm = toMicrofacetFrame(m, hLocal);
  const float hl = std::sqrt(glm::dot(hm, hm));
  if (hl > 0.0f) hm *= 1.0f / hl;  // R is a rotation; this only removes rounding
  const float d = ndf.D(hm);
  s.specular = std::isfinite(d) ? d : 0.0f;
  return s;
}

}  // namespace meso
