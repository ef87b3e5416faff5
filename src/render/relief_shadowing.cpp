// Becker & Max 1993, section 4.2: relief shadows in the far-field renderers, from the tabulated
// self-shadowing factor (DESIGN.md section 6, docs/shadows.md).
#include "meso/render/relief_shadowing.h"

#include "meso/render/level_shading.h"

#include <algorithm>
#include <cmath>

namespace meso {
namespace {

// The angles the BRDF and shadowing tables are looked up at.
struct TileAngles {
  ViewFrame f;
  float phiV = 0.0f;
};

TileAngles tileAngles(const TileMap& m, const Vec3& V) {
  TileAngles a;
  a.f = tileViewFrame(m.toTile(V));
  a.phiV = fastAtan2(a.f.T.y, a.f.T.x);  // the view's azimuth about the relief's axes
  return a;
}

// theta_L and phi_V - phi_L of a tile-space light direction lt (unit).
void lightAngles(const TileAngles& a, const Vec3& lt, float& thetaL, float& phiVL) {
  const Vec3 l = toFrame(a.f, lt);
  thetaL = fastAcos(l.z);
  phiVL = -fastAtan2(l.y, l.x);
}

bool blocked(const LightShadows* macro, size_t i) {
  return macro && (*macro)[i].diffuse <= 0.0f && (*macro)[i].specular <= 0.0f;
}

// The levels' factor for one light at its angles, times `start`: start * S_0 * S_1 ..., each S the
// two metric classes' tables mixed by w and clamped to [0, 1].
LightShadow levelsFactor(const ShadowingLevels& levels, LightShadow start, float thetaV, float phiV,
                         float thetaL, float phiVL, size_t first = 0,
                         size_t last = kMaxReliefLevels) {
  for (size_t k = first; k < std::min(levels.count, last); ++k) {
    const ShadowingTable& s0 = *levels.s0[k];
    const ShadowingTable& s1 = *levels.s1[k];
    if (s0.empty()) continue;
    ShadowingTable::Value v = s0.lookup(thetaV, phiV, thetaL, phiVL);
    if (levels.w > 0.0f && &s1 != &s0 && !s1.empty()) {
      const ShadowingTable::Value v1 = s1.lookup(thetaV, phiV, thetaL, phiVL);
      v.diffuse += levels.w * (v1.diffuse - v.diffuse);
      v.specular += levels.w * (v1.specular - v.specular);
    }
    start.diffuse *= std::clamp(v.diffuse, 0.0f, 1.0f);
    start.specular *= std::clamp(v.specular, 0.0f, 1.0f);
  }
  return start;
}

}  // namespace

LightShadows reliefShadowing(std::span<const Light> lights, const Vec3& P, const TileMap& m,
                             const Vec3& V, const ShadowingLevels& levels,
                             const LightShadows* macro) {
  LightShadows out;
  if (!levels.any()) return out;
  const TileAngles a = tileAngles(m, V);
  const size_t n = std::min(lights.size(), static_cast<size_t>(kMaxShadowedLights));
  for (size_t i = 0; i < n; ++i) {
    if (blocked(macro, i)) continue;
    const Vec3 lt = m.toTile(sampleLight(lights[i], P).L);
    const float len = glm::length(lt);
    if (!(lt.z > 0.0f) || !std::isfinite(len)) continue;
    float thetaL, phiVL;
    lightAngles(a, lt / len, thetaL, phiVL);
    out.light[i] = levelsFactor(levels, {}, a.f.thetaV, a.phiV, thetaL, phiVL);
  }
  return out;
}

Vec3 shadeBrdfShadowed(const Reflectance& material, std::span<const Light> lights, const Vec3& P,
                       const TileMap& m, const Vec3& V, const BrdfTable& t0, const BrdfTable& t1,
                       float w, const LightShadows& macro, const ShadowingLevels& levels,
                       LightShadows* firstLevel) {
  if (firstLevel) *firstLevel = {};
  Vec3 I = material.ka;
  const TileAngles a = tileAngles(m, V);
  const bool shadowed = levels.any();
  for (size_t i = 0; i < lights.size(); ++i) {
    if (blocked(&macro, i)) continue;
    const LightSample s = sampleLight(lights[i], P);
    const Vec3 lt = m.toTile(s.L);
    const float len = glm::length(lt);
    if (!(len > 0.0f) || !std::isfinite(len)) continue;
    // A light below the mean plane lights the facets that face it (the table goes on to theta_L =
    // pi), unless relief self-shadowing is on: then the relief around blocks every ray to it.
    if (!(lt.z > 0.0f) && shadowed) continue;
    float thetaL, phiVL;
    lightAngles(a, lt / len, thetaL, phiVL);
    LightShadow sh = macro[i];
    if (i < static_cast<size_t>(kMaxShadowedLights)) {
      if (firstLevel) {
        // The first level's own factor, then the others on top of macro times it: the same
        // products in the same order as one pass from macro.
        const LightShadow own = levelsFactor(levels, {}, a.f.thetaV, a.phiV, thetaL, phiVL, 0, 1);
        firstLevel->light[i] = own;
        sh = levelsFactor(levels, {sh.diffuse * own.diffuse, sh.specular * own.specular},
                          a.f.thetaV, a.phiV, thetaL, phiVL, 1);
      } else {
        sh = levelsFactor(levels, sh, a.f.thetaV, a.phiV, thetaL, phiVL);
      }
    }
    if (sh.diffuse <= 0.0f && sh.specular <= 0.0f) continue;
    BrdfTable::Value v = t0.lookup(a.f.thetaV, a.phiV, thetaL, phiVL);
    if (w > 0.0f && &t1 != &t0) {
      const BrdfTable::Value v1 = t1.lookup(a.f.thetaV, a.phiV, thetaL, phiVL);
      v.diffuse += w * (v1.diffuse - v.diffuse);
      v.specular += w * (v1.specular - v.specular);
    }
    I += s.radiance *
         (material.kd * (v.diffuse * len * sh.diffuse) + material.ks * (v.specular * sh.specular));
  }
  return I;
}

}  // namespace meso
