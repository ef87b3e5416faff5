// Relief self-shadowing (Becker & Max 1993, section 4.2; DESIGN.md section 6): the horizon march
// decides lit or blocked as a shadow ray through the periodic tile does, and the table it builds is
// the one traced with a shadow ray per hit and light.
#include "meso/appearance/shadowing_table.h"

#include "meso/core/rng.h"
#include "support/waves.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace meso {
namespace {

// Random periodic waves with integer frequencies up to 8 per tile: soft or steep by amplitude.
Waves randomWaves(uint64_t seed, float amplitude) {
  return meso::randomWaves(seed, amplitude, 8, 0, 9, -4, 9);
}

Vec3 toTile(const Vec3& w, const MetricShape& s) {
  return glm::normalize(Vec3(w.x / s.a - s.b * w.y, s.a * w.y, w.z));
}

// A tile direction along the horizontal unit u at elevation angle alpha.
Vec3 atElevation(Vec2 u, float alpha) {
  return glm::normalize(Vec3(u * std::cos(alpha), std::sin(alpha)));
}

// Visible points of the tile seen from random views, just off the surface as the table's hits.
Vec3 randomVisiblePoint(const PeriodicRelief& relief, const PeriodicTile& tile, Rng& rng) {
  for (;;) {
    const float theta = radians(80.0f) * rng.uniform(), phi = 2.0f * kPi * rng.uniform();
    const Vec3 eye(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                   std::cos(theta));
    Vec3 p;
    if (!tile.traceHit(Vec3(rng.uniform(), rng.uniform(), tile.zMax() + 1e-3f), -eye, p)) continue;
    const Vec2 g = relief.gradient(p.x, p.y);
    return p + 1e-4f * glm::normalize(Vec3(-g.x, -g.y, 1.0f));
  }
}

// At random visible points and light azimuths, 12 random light elevations decided by one horizon
// march each agree with a shadow ray each; where they differ, the light grazes the horizon (the
// ray 0.05 degrees lower is blocked and 0.05 degrees higher is free).
void expectHorizonDecidesLikeShadowRays(const PeriodicRelief& relief, const MetricShape& shape,
                                        const char* name) {
  const PeriodicTile tile(relief, 96);
  Rng rng(5);
  int decisions = 0, differ = 0, blocked = 0;
  for (int sample = 0; sample < 4000; ++sample) {
    const Vec3 p = randomVisiblePoint(relief, tile, rng);
    const float phiL = 2.0f * kPi * rng.uniform();
    const Vec3 horizontal = toTile(Vec3(std::cos(phiL), std::sin(phiL), 0.0f), shape);
    const Vec2 u = glm::normalize(Vec2(horizontal));
    std::vector<float> alphas(12);
    for (float& a : alphas) a = 0.5f * kPi * rng.uniform();
    std::sort(alphas.begin(), alphas.end());
    std::vector<float> slopes;
    for (float a : alphas) slopes.push_back(std::tan(a));
    const float horizon = tile.horizon(p, u, slopes, kShadowMaxTiles);
    for (size_t q = 0; q < alphas.size(); ++q) {
      const bool free = !tile.occluded(p, atElevation(u, alphas[q]), kShadowMaxTiles);
      ++decisions;
      blocked += free ? 0 : 1;
      if (free == (slopes[q] > horizon)) continue;
      ++differ;
      const float band = radians(0.05f);
      EXPECT_TRUE(tile.occluded(p, atElevation(u, alphas[q] - band), kShadowMaxTiles) &&
                  !tile.occluded(p, atElevation(u, alphas[q] + band), kShadowMaxTiles))
          << name << ": at (" << p.x << ", " << p.y << ", " << p.z << ") towards (" << u.x << ", "
          << u.y << ") elevation " << degrees(alphas[q]) << ", horizon slope " << horizon;
    }
  }
  EXPECT_LT(differ, decisions / 1000) << name;
  // Not a vacuous test: the relief blocks a fair share of the lights.
  EXPECT_GT(blocked, decisions / 20) << name;
  EXPECT_LT(blocked, decisions / 2) << name;
}

// Right at the horizon: the critical elevation found by bisection with shadow rays, and lights
// 0.001 degrees below and above it, are decided as the rays decide them.
void expectHorizonAtTheCriticalElevation(const PeriodicRelief& relief, const char* name) {
  const PeriodicTile tile(relief, 96);
  Rng rng(6);
  const float band = radians(1e-3f);
  for (int sample = 0; sample < 300; ++sample) {
    const Vec3 p = randomVisiblePoint(relief, tile, rng);
    const float phiL = 2.0f * kPi * rng.uniform();
    const Vec2 u(std::cos(phiL), std::sin(phiL));
    float lo = 0.0f, hi = 0.5f * kPi;  // blocked at lo, free at hi
    if (!tile.occluded(p, atElevation(u, lo), kShadowMaxTiles)) continue;
    for (int step = 0; step < 40; ++step) {
      const float mid = 0.5f * (lo + hi);
      (tile.occluded(p, atElevation(u, mid), kShadowMaxTiles) ? lo : hi) = mid;
    }
    const std::vector<float> slopes = {std::tan(lo - band), std::tan(hi + band)};
    const float horizon = tile.horizon(p, u, slopes, kShadowMaxTiles);
    EXPECT_TRUE(slopes[0] <= horizon && slopes[1] > horizon)
        << name << ": at (" << p.x << ", " << p.y << ", " << p.z << ") towards (" << u.x << ", "
        << u.y << ") the rays' horizon is at " << degrees(lo) << " degrees, the march's slope "
        << horizon << " (" << degrees(std::atan(horizon)) << " degrees)";
  }
}

TEST(ShadowingTable, HorizonDecidesLikeAShadowRayOnASoftRelief) {
  const Waves soft = randomWaves(3, 0.004f);
  expectHorizonDecidesLikeShadowRays(soft, {}, "soft");
  expectHorizonDecidesLikeShadowRays(soft, {1.6f, 0.4f}, "soft, sheared");
  expectHorizonAtTheCriticalElevation(soft, "soft");
}

TEST(ShadowingTable, HorizonDecidesLikeAShadowRayOnASteepRelief) {
  const Waves steep = randomWaves(4, 0.03f);
  expectHorizonDecidesLikeShadowRays(steep, {}, "steep");
  expectHorizonDecidesLikeShadowRays(steep, {0.7f, -0.5f}, "steep, sheared");
  expectHorizonAtTheCriticalElevation(steep, "steep");
}

// The same hits decided by horizon marches and by shadow rays: the tables agree but for the few
// hits whose light grazes their horizon.
void expectTableEqualsShadowRayTable(const PeriodicRelief& relief, const MetricShape& shape,
                                     int phiV) {
  const PeriodicTile tile(relief, 96);
  const VisibleNormalHistogram layout({4, 8, 8, phiV}, 1.5533430f,
                                      VisibleNormalHistogram::LayoutOnly{});
  HistogramSettings hs;
  hs.shape = shape;
  ShadowingResolution res;
  res.thetaL = 7;
  res.phi = 4;
  res.thetaVRefine = 1;
  res.raysPerSlice = phiV > 1 ? 256 : 32;
  const ShadowingTable marched = ShadowingTable::trace(relief, tile, layout, hs, res, 20.0f, 9);
  const ShadowingTable traced =
      ShadowingTable::traceWithShadowRays(relief, tile, layout, hs, res, 20.0f, 9);
  ASSERT_EQ(marched.numThetaV(), traced.numThetaV());
  double worst = 0.0, sum = 0.0, shadowed = 0.0;
  int entries = 0;
  for (int k = 0; k < traced.numThetaV() * traced.numPhiV(); ++k)
    for (int i = 0; i < traced.numDelta(); ++i)
      for (int j = 0; j < ShadowingTable::phiNodes(res, phiV); ++j) {
        const ShadowingTable::Value a = marched.entry(k, i, j), b = traced.entry(k, i, j);
        for (double d : {a.diffuse - b.diffuse, a.specular - b.specular}) {
          worst = std::max(worst, std::abs(d));
          sum += std::abs(d);
          ++entries;
        }
        shadowed += 1.0 - b.diffuse;
      }
  EXPECT_LT(worst, 0.01) << "phiV " << phiV;
  EXPECT_LT(sum / entries, 1e-4) << "phiV " << phiV;
  EXPECT_GT(shadowed / (entries / 2), 0.05) << "phiV " << phiV;  // the relief shadows itself
}

TEST(ShadowingTable, EqualsTheShadowRayTable) {
  const Waves steep = randomWaves(4, 0.03f);
  expectTableEqualsShadowRayTable(steep, {}, 1);
  expectTableEqualsShadowRayTable(steep, {1.3f, 0.3f}, 4);
}

}  // namespace
}  // namespace meso
