// L(r1, r2) (Kautz et al. 2001, section 4): inverse round trips, moments of sharp and anisotropic
// Beckmann, and finite unit normals for extreme NDFs.
#include "meso/core/error.h"
#include "meso/core/rng.h"
#include "meso/synthesis/beckmann_ndf.h"
#include "meso/synthesis/blinn_phong_ndf.h"
#include "meso/synthesis/normal_lookup_table.h"
#include "meso/synthesis/tabulated_ndf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

namespace meso {
namespace {

TEST(NormalLookupTable, WarpInvertsAndCrowdsTheEnds) {
  for (int k = 0; k <= 100; ++k) {
    const float t = k / 100.0f;
    EXPECT_NEAR(NormalLookupTable::unwarp(NormalLookupTable::warp(t)), t,
                1e-5f);  // float near r = 1
  }
  EXPECT_LT(NormalLookupTable::warp(1.0f / 255.0f), 3e-7f);  // the first cell's mass
}

TEST(NormalLookupTable, ForwardCdfInvertsTheExactSample) {
  const BeckmannNdf ndf(0.2f, 0.5f);
  const NormalLookupTable table(ndf);
  Rng rng(1, 2);
  for (int k = 0; k < 2000; ++k) {
    const Vec2 r(rng.uniform(), rng.uniform());
    const Vec2 back = table.cdf(table.sampleExact(r));
    EXPECT_NEAR(back.x, r.x, 2e-4f);
    EXPECT_NEAR(back.y, r.y, 2e-4f);
  }
}

TEST(NormalLookupTable, InvertIsTheInverseOfLookup) {
  const BeckmannNdf ndf(0.3f, 0.1f);
  const NormalLookupTable table(ndf);
  Rng rng(3, 4);
  float worst = 0.0f;
  for (int k = 0; k < 5000; ++k) {
    const Vec2 r(rng.uniform(), rng.uniform());
    const Vec3 m = table.lookup(r);
    const Vec3 again = table.lookup(table.invert(m));
    worst = std::max(worst, glm::length(again - m));
  }
  EXPECT_LT(worst, 1e-5f);
  // The bilinear table is close to the exact sample: within a cell.
  for (int k = 0; k < 2000; ++k) {
    const Vec2 r(rng.uniform(), rng.uniform());
    const float d = std::acos(std::min(1.0f, glm::dot(table.lookup(r), table.sampleExact(r))));
    EXPECT_LE(d, table.cellAngle(r) + 1e-3f);
  }
}

// E[tan^2 theta] = alpha^2 for isotropic Beckmann; E[(m.x / m.z)^2] = alpha_x^2 / 2: from a
// stratified grid of (r1, r2) through L.
void expectBeckmannMoments(float ax, float ay) {
  const BeckmannNdf ndf(ax, ay);
  const NormalLookupTable table(ndf);
  const int n = 400;
  double sx = 0.0, sy = 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const Vec3 m = table.lookup(Vec2((i + 0.5f) / n, (j + 0.5f) / n));
      ASSERT_TRUE(isFinite(m));
      sx += (m.x / m.z) * (m.x / m.z), sy += (m.y / m.z) * (m.y / m.z);
    }
  sx /= n * n, sy /= n * n;
  EXPECT_NEAR(sx, ax * ax / 2.0, 0.02 * ax * ax / 2.0) << ndf.name();
  EXPECT_NEAR(sy, ay * ay / 2.0, 0.02 * ay * ay / 2.0) << ndf.name();
}

TEST(NormalLookupTable, BeckmannSlopeMomentsFromSharpToRough) {
  expectBeckmannMoments(1e-4f, 1e-4f);
  expectBeckmannMoments(0.05f, 0.3f);
  expectBeckmannMoments(0.5f, 0.5f);
}

TEST(NormalLookupTable, FiniteUnitNormalsForExtremeNdfs) {
  std::vector<std::unique_ptr<Ndf>> ndfs;
  ndfs.push_back(std::make_unique<BeckmannNdf>(1e-4f));
  ndfs.push_back(std::make_unique<BeckmannNdf>(1e4f));
  ndfs.push_back(std::make_unique<BeckmannNdf>(1e-4f, 3.0f));
  ndfs.push_back(std::make_unique<BlinnPhongNdf>(0.0f));
  ndfs.push_back(std::make_unique<BlinnPhongNdf>(1e6f));
  ndfs.push_back(std::make_unique<TabulatedNdf>(4, 4, std::vector<float>(16, 1.0f)));
  std::vector<float> spike(64 * 64, 0.0f);
  spike[32 * 64 + 40] = 1.0f;
  ndfs.push_back(std::make_unique<TabulatedNdf>(64, 64, spike));
  for (const auto& ndf : ndfs) {
    const NormalLookupTable table(*ndf, NormalLookupOptions{64, 64, 2});
    for (float a : {0.0f, 1e-7f, 0.3f, 0.5f, 1.0f - 1e-7f, 1.0f, -1.0f, 2.0f})
      for (float b : {0.0f, 0.5f, 1.0f}) {
        const Vec3 m = table.lookup(Vec2(a, b));
        ASSERT_TRUE(isFinite(m)) << ndf->name() << " " << a << " " << b;
        EXPECT_NEAR(glm::length(m), 1.0f, 1e-5f) << ndf->name();
        EXPECT_GT(m.z, 0.0f) << ndf->name();
        const Vec2 r = table.invert(m);
        EXPECT_TRUE(r.x >= 0.0f && r.x <= 1.0f && r.y >= 0.0f && r.y <= 1.0f) << ndf->name();
      }
  }
  EXPECT_THROW(NormalLookupTable(BeckmannNdf(0.3f), NormalLookupOptions{1, 64, 2}), Error);
}

}  // namespace
}  // namespace meso
