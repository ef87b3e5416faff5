// Becker & Max 1993, section 2.1: for uncorrelated levels, the BRDF of the coarse level built over
// the fine level's BRDF (Figure 2, second branch) matches the one-level BRDF of the combined
// relief.
#include "meso/appearance/level_tables.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace meso {
namespace {

constexpr float kCoarse = 0.05f, kFine = 0.006f;
constexpr int kFineCycles = 8;  // the fine level repeats 8 times per coarse tile

// Low band: one bump per tile.
struct Coarse : PeriodicRelief {
  float height(float x, float y) const override {
    return kCoarse * std::sin(2 * kPi * x) * std::sin(2 * kPi * y);
  }
  Vec2 gradient(float x, float y) const override {
    return {kCoarse * 2 * kPi * std::cos(2 * kPi * x) * std::sin(2 * kPi * y),
            kCoarse * 2 * kPi * std::sin(2 * kPi * x) * std::cos(2 * kPi * y)};
  }
  uint64_t fingerprint() const override { return 1; }
};

// High band on its own tile (one period scaled to the unit tile: heights scale with it).
struct Fine : PeriodicRelief {
  float height(float x, float y) const override {
    return kFineCycles * kFine * (std::sin(2 * kPi * x) + std::cos(2 * kPi * y));
  }
  Vec2 gradient(float x, float y) const override {
    return {kFineCycles * kFine * 2 * kPi * std::cos(2 * kPi * x),
            -kFineCycles * kFine * 2 * kPi * std::sin(2 * kPi * y)};
  }
  uint64_t fingerprint() const override { return 2; }
};

// Both bands on the coarse tile.
struct Combined : PeriodicRelief {
  Coarse c;
  float height(float x, float y) const override {
    return c.height(x, y) +
           kFine * (std::sin(2 * kPi * kFineCycles * x) + std::cos(2 * kPi * kFineCycles * y));
  }
  Vec2 gradient(float x, float y) const override {
    const float k = 2 * kPi * kFineCycles;
    return c.gradient(x, y) + Vec2(kFine * k * std::cos(k * x), -kFine * k * std::sin(k * y));
  }
  uint64_t fingerprint() const override { return 3; }
};

TEST(TwoLevelBrdf, RecursionMatchesTheCombinedRelief) {
  TableSettings s;
  s.histogram.resolution = {9, 96, 32};
  s.histogram.meshResolution = 256;  // resolves the fine band on the combined tile
  const TableCache none{std::filesystem::path()};
  const LevelTables fine = buildLevelTables(Fine(), 20.0f, s, nullptr, none, nullptr);
  const LevelTables twoLevel = buildLevelTables(Coarse(), 20.0f, s, &fine, none, nullptr);
  const LevelTables oneLevel = buildLevelTables(Combined(), 20.0f, s, nullptr, none, nullptr);
  // Stated tolerance: 0.015 absolute and 3% relative (where the value exceeds 0.25) for theta_V up
  // to 78 and theta_L up to 66 degrees; measured 0.0086 and 2.3%. Towards grazing light the
  // recursion is worse (measured 0.024 and 6% at theta_L = 90): it reads the finer table at primed
  // angles near theta'_L = 90 degrees, where 16 trilinear nodes resolve the falloff least well.
  double worstAbs = 0.0, worstRel = 0.0;
  for (int k = 0; k < twoLevel.brdf.numThetaV() - 1; ++k)            // theta_V up to 78 degrees
    for (int i = 0; i < twoLevel.brdf.resolution().thetaL - 4; ++i)  // theta_L up to 66 degrees
      for (int j = 0; j < twoLevel.brdf.resolution().phi; ++j) {
        const double a = twoLevel.brdf.entry(k, i, j).diffuse,
                     b = oneLevel.brdf.entry(k, i, j).diffuse;
        worstAbs = std::max(worstAbs, std::abs(a - b));
        if (b > 0.25) worstRel = std::max(worstRel, std::abs(a - b) / b);
      }
  std::printf(
      "two-level vs combined BRDF_diff: worst absolute %.4f, worst relative (value > 0.25) %.4f\n",
      worstAbs, worstRel);
  EXPECT_LT(worstAbs, 0.015);
  EXPECT_LT(worstRel, 0.03);
}

}  // namespace
}  // namespace meso
