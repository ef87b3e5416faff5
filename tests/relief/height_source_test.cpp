// A relief level: world height amplitude * h(S u, S v) and its derivatives by the chain rule.
#include "meso/relief/height_source.h"
#include "meso/core/rng.h"
#include "meso/relief/fractal_noise.h"
#include "meso/relief/height_table.h"
#include "meso/relief/relief_level.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <optional>

namespace meso {
namespace {

TEST(HeightLevel, ChainRule) {
  const FractalNoise noise(3, 2.0f, 0.5f, 3);
  const HeightLevel level = HeightLevel::make(noise, 0.05f, 4.0f);
  EXPECT_FLOAT_EQ(level.freq, 16.0f * 4.0f);  // 4 * 2^2 cells per tile, S = 4
  EXPECT_FLOAT_EQ(level.wavelength(), 1.0f / 64.0f);
  Rng rng(2);
  for (int k = 0; k < 100; ++k) {
    const Vec2 uv(rng.uniform(), rng.uniform());
    EXPECT_FLOAT_EQ(level.height(uv), 0.05f * noise.height(4.0f * uv));
    const float e = 1.0f / 65536;
    const Vec2 fd((level.height(uv + Vec2(e, 0)) - level.height(uv - Vec2(e, 0))) / (2 * e),
                  (level.height(uv + Vec2(0, e)) - level.height(uv - Vec2(0, e))) / (2 * e));
    const Vec2 B = level.derivatives(uv);
    EXPECT_LT(glm::length(B - fd), 2e-3f * (1.0f + glm::length(B))) << uv.x << " " << uv.y;
  }
}

// A level's second derivative along a (u, v) direction carries amplitude and scale by the chain
// rule: it matches central differences of the level's own derivatives (the crest curvature's
// former formula, which sources without it still use). A table has none.
TEST(ReliefLevel, SecondDerivativeAlongADirectionFollowsTheChainRule) {
  ReliefLevel level;
  level.source = std::make_unique<FractalNoise>(3, 2.0f, 0.5f, 3);
  level.amplitude = 0.3f;
  level.scale = 0.125f;
  level.freqPerU = level.source->highestFrequency() * level.scale;
  Rng rng(4);
  double worst = 0.0, square = 0.0;
  for (int k = 0; k < 200; ++k) {
    const ReliefCoord c{Vec2(8.0f * rng.uniform(), 8.0f * rng.uniform())};
    const Vec2 w = (0.5f + rng.uniform()) * glm::normalize(Vec2(rng.uniform() - 0.5f, 0.3f));
    const std::optional<float> d2 = level.secondDerivative(c, w);
    ASSERT_TRUE(d2.has_value());
    const float h = level.wavelength() / 1024.0f;
    const double fd =
        glm::dot(level.derivatives(c.offset(h * w)) - level.derivatives(c.offset(-h * w)), w) /
        (2.0 * h);
    worst = std::max(worst, std::abs(fd - *d2));
    square += fd * fd;
  }
  // Measured 1e-3 of the RMS; amplitude or scale missing or squared would be off by 3x or more.
  EXPECT_LT(worst / std::sqrt(square / 200.0), 0.01);
  ReliefLevel table;
  table.source = std::make_unique<HeightTable>(4, 4, std::vector<float>(16, 0.5f));
  EXPECT_FALSE(table.secondDerivative(ReliefCoord{Vec2(0.5f)}, Vec2(1.0f, 0.0f)).has_value());
}

TEST(HeightLevel, TableLevelRepeatsEveryOneOverS) {
  std::vector<float> t(16 * 16);
  for (int k = 0; k < 256; ++k) t[k] = std::sin(0.3f * k);
  const HeightTable table(16, 16, t);
  const HeightLevel level = HeightLevel::make(table, 2.0f, 8.0f);
  EXPECT_FLOAT_EQ(level.freq, table.highestFrequency() * 8.0f);
  const Vec2 uv(0.0625f, 0.3125f);
  EXPECT_FLOAT_EQ(level.height(uv), level.height(uv + Vec2(0.125f, 0.0f)));
  EXPECT_EQ(level.derivatives(uv), 16.0f * table.gradient(8.0f * uv));
}

// heightAndGradient is height and gradient at once, bit for bit: the default of the interface (a
// height table) and fBm's own one-pass version (whose values the tessellator's offsets reuse from
// the derivatives T needs).
TEST(HeightSource, HeightAndGradientAtOnceAreTheSameBits) {
  std::vector<float> t(16 * 16);
  for (int k = 0; k < 256; ++k) t[k] = std::sin(0.3f * k) + 0.1f * std::cos(1.7f * k);
  const HeightTable table(16, 16, t);
  const FractalNoise noise(3, 2.0f, 0.5f, 5);
  Rng rng(4);
  for (const HeightSource* source :
       {static_cast<const HeightSource*>(&table), static_cast<const HeightSource*>(&noise)})
    for (int k = 0; k < 200; ++k) {
      const Vec2 p(4.0f * rng.uniform() - 2.0f, 4.0f * rng.uniform() - 2.0f);
      Vec2 g;
      EXPECT_EQ(source->heightAndGradient(p, g), source->height(p));
      EXPECT_EQ(g, source->gradient(p));
    }
}

}  // namespace
}  // namespace meso
