// Becker & Max 1993, sections 2.1 (BRDF lookup), 3 (redistribution) and 4.1 (theta_W).
#include "meso/render/level_shading.h"

#include "meso/render/shading.h"

#include <algorithm>
#include <cmath>

namespace meso {
namespace {

Vec3 perpendicularTo(const Vec3& n) {
  const Vec3 a = std::abs(n.x) < 0.9f ? Vec3(1.0f, 0.0f, 0.0f) : Vec3(0.0f, 1.0f, 0.0f);
  return glm::normalize(a - glm::dot(a, n) * n);
}

}  // namespace

ViewFrame makeViewFrame(const Vec3& N, const Vec3& V, const Vec3& tangentHint) {
  ViewFrame f;
  f.N = N;
  const float c = std::clamp(glm::dot(V, N), 0.0f, 1.0f);
  f.thetaV = fastAcos(c);
  Vec3 t = V - glm::dot(V, N) * N;
  float len = glm::length(t);
  if (len < 1e-6f) {
    t = tangentHint - glm::dot(tangentHint, N) * N;
    len = glm::length(t);
  }
  f.T = len > 1e-6f && std::isfinite(len) ? t / len : perpendicularTo(N);
  f.B = glm::cross(f.N, f.T);
  return f;
}

Vec3 redistributeNormal(const Redistribution& r, const ViewFrame& f, float disp,
                        const Vec3& nBump) {
  if (disp >= 1.0f)
    return nBump;  // fully displaced: the Blinn normal itself, not a round trip of it
  const NormalAngles in = anglesOf(toFrame(f, nBump));
  const NormalAngles out = r.partial(f.thetaV, disp, in);
  return fromFrame(f, normalOf(out));
}

float azimuthEq2(const Vec3& V, const Vec3& L, const Vec3& Pu, const Vec3& Pv) {
  const Vec2 Vn(glm::dot(V, Pu), glm::dot(V, Pv)), Ln(glm::dot(L, Pu), glm::dot(L, Pv));
  const float a = glm::length(Vn), b = glm::length(Ln);
  if (!(a > 1e-6f * (glm::length(Pu) + glm::length(Pv))) ||
      !(b > 1e-6f * (glm::length(Pu) + glm::length(Pv))))
    return -1.0f;
  const float c = glm::dot(Vn, Ln) / (a * b);
  return std::isfinite(c) ? fastAcos(c) : -1.0f;
}

Vec3 shadeBrdf(const Reflectance& material, std::span<const Light> lights, const Vec3& P,
               const ViewFrame& f, const BrdfTable& brdf, const Vec3* Pu, const Vec3* Pv) {
  Vec3 I = material.ka;
  const Vec3 V = std::sin(f.thetaV) * f.T + std::cos(f.thetaV) * f.N;
  for (const Light& light : lights) {
    const LightSample s = sampleLight(light, P);
    const Vec3 l = toFrame(f, s.L);
    // A light below the mean plane still lights the facets that face it: the table goes on to
    // theta_L = pi.
    const float thetaL = fastAcos(l.z);
    const float eq2 = Pu && Pv ? azimuthEq2(V, s.L, *Pu, *Pv) : -1.0f;
    const float phiVL =
        eq2 >= 0.0f ? eq2 : std::abs(fastAtan2(l.y, l.x));  // V has azimuth 0 in the frame
    const BrdfTable::Value v = brdf.lookup(f.thetaV, thetaL, phiVL);
    I += s.radiance * (material.kd * v.diffuse + material.ks * v.specular);
  }
  return I;
}

ViewFrame tileViewFrame(const Vec3& v) {
  const float len = glm::length(v);
  return makeViewFrame(Vec3(0.0f, 0.0f, 1.0f),
                       len > 0.0f && std::isfinite(len) ? v / len : Vec3(0, 0, 1),
                       Vec3(1.0f, 0.0f, 0.0f));
}

namespace {

Vec3 normalizedOr(const Vec3& v, const Vec3& fallback) {
  const float len = glm::length(v);
  return len > 0.0f && std::isfinite(len) ? v / len : fallback;
}

}  // namespace

Vec3 redistributeNormal(const Redistribution& r, const TileMap& m, const Vec3& V, float disp,
                        const Vec3& nBump) {
  if (disp >= 1.0f) return nBump;
  const Vec3 vt = m.toTile(V);
  const ViewFrame f = tileViewFrame(vt);
  const Vec3 nTile = normalizedOr(m.normalToTile(nBump), Vec3(0, 0, 1));
  const NormalAngles out =
      r.partial(f.thetaV, fastAtan2(f.T.y, f.T.x), disp, anglesOf(toFrame(f, nTile)));
  return normalizedOr(m.normalToWorld(fromFrame(f, normalOf(out))), m.N);
}

}  // namespace meso
