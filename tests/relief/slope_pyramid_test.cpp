// Schilling: the roughness pyramid's recursive rule equals the covariance of all finest slopes.
#include "meso/relief/slope_pyramid.h"
#include "meso/core/error.h"
#include "meso/core/rng.h"
#include "meso/relief/fractal_noise.h"

#include <gtest/gtest.h>

#include <cmath>

namespace meso {
namespace {

HeightTable randomTable(int w, int h) {
  Rng rng(8);
  std::vector<float> t(static_cast<size_t>(w) * h);
  for (float& v : t) v = rng.uniform();
  return HeightTable(w, h, std::move(t));
}

// Waves along u only: every f_v is 0, so K is singular (c = 0).
HeightTable uOnly(int w, int h) {
  std::vector<float> t(static_cast<size_t>(w) * h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      t[static_cast<size_t>(j) * w + i] =
          std::sin(2 * kPi * 3 * (i + 0.5f) / w) + 0.1f * ((i * 7) % 5);
  return HeightTable(w, h, std::move(t));
}

struct Direct {
  double fu = 0, fv = 0, a = 0, b = 0, c = 0;
};

// Mean and (population) covariance of the level-0 slopes under texel (i, j) of level l.
Direct direct(const SlopePyramid& p, int l, int i, int j) {
  const int bw = p.width(0) / p.width(l), bh = p.height(0) / p.height(l);
  Direct d;
  const double n = static_cast<double>(bw) * bh;
  for (int y = j * bh; y < (j + 1) * bh; ++y)
    for (int x = i * bw; x < (i + 1) * bw; ++x)
      d.fu += p.slope(0, x, y).x / n, d.fv += p.slope(0, x, y).y / n;
  for (int y = j * bh; y < (j + 1) * bh; ++y)
    for (int x = i * bw; x < (i + 1) * bw; ++x) {
      const double u = p.slope(0, x, y).x - d.fu, v = p.slope(0, x, y).y - d.fv;
      d.a += u * u / n, d.b += u * v / n, d.c += v * v / n;
    }
  return d;
}

void expectEquivalence(const SlopePyramid& p) {
  const Direct all = direct(p, p.levels() - 1, 0, 0);
  const double scale = std::max(all.a, all.c);
  ASSERT_GT(scale, 0.0);
  for (int l = 1; l < p.levels(); ++l)
    for (int j = 0; j < p.height(l); ++j)
      for (int i = 0; i < p.width(l); ++i) {
        const Direct d = direct(p, l, i, j);
        const SlopeCovariance K = covarianceOf(p.roughness(l, i, j));
        EXPECT_NEAR(K.a, d.a, 1e-5 * scale) << "level " << l << " texel " << i << "," << j;
        EXPECT_NEAR(K.b, d.b, 1e-5 * scale) << "level " << l << " texel " << i << "," << j;
        EXPECT_NEAR(K.c, d.c, 1e-5 * scale) << "level " << l << " texel " << i << "," << j;
        EXPECT_NEAR(p.slope(l, i, j).x, d.fu, 1e-5 * std::sqrt(scale));
        EXPECT_NEAR(p.slope(l, i, j).y, d.fv, 1e-5 * std::sqrt(scale));
      }
}

TEST(SlopePyramid, RoughnessEqualsCovarianceOfTheFinestSlopes) {
  const HeightTable t = randomTable(32, 32);
  const SlopePyramid p(t);
  ASSERT_EQ(p.levels(), 6);
  // Level 0 is the slope map: the quadratic derivative at texel centres, i.e. central differences.
  EXPECT_NEAR(p.slope(0, 5, 7).x, 0.5f * (t.texel(6, 7) - t.texel(4, 7)) * 32, 1e-4f);
  EXPECT_NEAR(p.slope(0, 5, 7).y, 0.5f * (t.texel(5, 8) - t.texel(5, 6)) * 32, 1e-4f);
  EXPECT_EQ(covarianceOf(p.roughness(0, 5, 7)).a, 0.0f);
  expectEquivalence(p);
  expectEquivalence(SlopePyramid(randomTable(32, 8)));  // non-square: 2 x 1 boxes at the top
}

TEST(SlopePyramid, AnisotropicReliefHasSingularCovariance) {
  const SlopePyramid p(uOnly(32, 16));
  expectEquivalence(p);
  for (int l = 0; l < p.levels(); ++l) {
    const RoughnessFactor D = p.roughness(l, 0, 0);
    EXPECT_EQ(D.d3, 0.0f);
    EXPECT_EQ(D.d2, 0.0f);
    EXPECT_TRUE(std::isfinite(D.d1));
  }
  EXPECT_GT(p.roughness(3, 1, 0).d1, 0.0f);
}

TEST(SlopePyramid, FootprintSelectsTheLevelAndInterpolates) {
  const HeightTable t = randomTable(32, 32);
  const SlopePyramid p(t);
  // A texel centre of level 2 with a footprint of 4 level-0 texels: that texel exactly.
  const Vec2 centre((5 + 0.5f) / 8, (2 + 0.5f) / 8);
  const SlopeSample s = p.lookup(centre, Vec2(4.0f, 0.0f), Vec2(0.0f, 1.0f));
  EXPECT_FLOAT_EQ(s.lod, 2.0f);
  EXPECT_NEAR(s.mean.x, p.slope(2, 5, 2).x, 1e-5f);
  const SlopeCovariance K = covarianceOf(p.roughness(2, 5, 2));
  EXPECT_NEAR(s.roughness.a, K.a, 1e-4f * K.a);
  EXPECT_NEAR(s.roughness.b, K.b, 1e-4f * K.a);
  // Half way between levels 1 and 2: the average of the two bilinear lookups.
  const Vec2 q(0.3f, 0.71f);
  const SlopeSample half =
      p.lookup(q, Vec2(2.0f, 2.0f), Vec2(0.5f, -0.5f));  // |dx| = 2 sqrt(2): lod 1.5
  const SlopeSample l1 = p.lookupLevel(q, 1.0f), l2 = p.lookupLevel(q, 2.0f);
  EXPECT_NEAR(half.lod, 1.5f, 1e-6f);
  EXPECT_NEAR(half.mean.x, 0.5f * (l1.mean.x + l2.mean.x), 1e-5f);
  EXPECT_NEAR(half.roughness.c, 0.5f * (l1.roughness.c + l2.roughness.c), 1e-4f);
  // Magnification: level 0, no extra roughness. A huge footprint: the whole tile.
  EXPECT_EQ(p.lookup(q, Vec2(0.1f, 0.0f), Vec2(0.0f, 0.2f)).roughness.a, 0.0f);
  const SlopeSample top = p.lookup(q, Vec2(1e9f, 0.0f), Vec2(0.0f));
  EXPECT_EQ(top.lod, 5.0f);
  const Direct all = direct(p, 5, 0, 0);
  EXPECT_NEAR(top.roughness.a, all.a, 1e-4 * all.a);
  // Periodic addressing.
  EXPECT_NEAR(p.lookupLevel(q + Vec2(3.0f, -2.0f), 1.3f).mean.y, p.lookupLevel(q, 1.3f).mean.y,
              1e-4f);
}

TEST(SlopePyramid, ScalesToALevel) {
  const SlopeSample s{Vec2(1.0f, -2.0f), SlopeCovariance{4.0f, 1.0f, 2.0f}, 1.0f};
  const SlopeSample k = s.scaled(0.5f);
  EXPECT_EQ(k.mean, Vec2(0.5f, -1.0f));
  EXPECT_EQ(k.roughness.a, 1.0f);
  EXPECT_EQ(k.roughness.b, 0.25f);
}

TEST(SlopePyramid, SizesAndExtremes) {
  const SlopePyramid odd(randomTable(20, 12));  // resampled to 32 x 16
  EXPECT_EQ(odd.width(), 32);
  EXPECT_EQ(odd.height(), 16);
  const FractalNoise noise(3, 2.0f, 0.5f, 5);
  EXPECT_THROW(SlopePyramid(noise, 48, 64), Error);
  const SlopePyramid p(noise, 64, 64);
  EXPECT_EQ(p.levels(), 7);
  for (float w : {0.0f, 1e-30f, 1e30f, INFINITY, NAN}) {
    const SlopeSample s = p.lookup(Vec2(w, 0.2f), Vec2(w, 0.0f), Vec2(0.0f, w));
    EXPECT_TRUE(std::isfinite(s.mean.x) && std::isfinite(s.mean.y) &&
                std::isfinite(s.roughness.a) && std::isfinite(s.roughness.b) &&
                std::isfinite(s.roughness.c) && std::isfinite(s.lod))
        << w;
  }
}

}  // namespace
}  // namespace meso
