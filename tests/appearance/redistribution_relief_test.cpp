// Redistribution on real reliefs: Blinn normals sampled uniformly over the tile and mapped by
// R_theta follow the traced visible-normal distribution distr[theta] (chi-square, alpha 0.01 with
// Sidak correction over the tested slices and variants).
#include "meso/appearance/level_tables.h"

#include "meso/core/rng.h"
#include "support/chi_square.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace meso {
namespace {

struct Bumps : PeriodicRelief {
  float height(float x, float y) const override {
    return 0.06f * (std::sin(2 * kPi * x) * std::sin(2 * kPi * y) + 0.4f * std::cos(2 * kPi * (x + 2 * y)));
  }
  Vec2 gradient(float x, float y) const override {
    const float c = 0.06f * 2 * kPi;
    return {c * (std::cos(2 * kPi * x) * std::sin(2 * kPi * y) - 0.4f * std::sin(2 * kPi * (x + 2 * y))),
            c * (std::sin(2 * kPi * x) * std::cos(2 * kPi * y) - 0.8f * std::sin(2 * kPi * (x + 2 * y)))};
  }
  uint64_t fingerprint() const override { return 11; }
};

// Merges the phi bins into groups so that expected counts stay large where the mass is.
TEST(RedistributionOnRelief, MappedBlinnNormalsFollowTheVisibleDistribution) {
  const Bumps relief;
  TableSettings settings;
  settings.histogram.resolution = {9, 96, 32};  // the default theta_N and phi resolution
  settings.histogram.azimuths = 32;
  settings.histogram.raysPerView = 8192;  // 262k rays per slice: the tables' own noise stays small
  const TableCache none{std::filesystem::path()};
  const int slices[] = {3, 6, 8};  // 33, 67 and 89 degrees
  const double alpha = testing::sidakAlpha(0.01, 2 * 3);
  for (auto variant : {RedistributionVariant::Separable, RedistributionVariant::Conditional}) {
    settings.variant = variant;
    const LevelTables t = buildLevelTables(relief, 20.0f, settings, nullptr, none, nullptr);
    const VisibleNormalHistogram& h = t.distr;
    for (int k : slices) {
      constexpr int kSamples = 20000;
      Rng rng(1000 + k);
      std::vector<double> observed(96, 0.0), expected(96, 0.0);
      // The separable maps reproduce the theta_N marginal; the conditional ones the joint. Test
      // the theta_N marginal for both (it is what the diffuse term sees most).
      for (int n = 0; n < kSamples; ++n) {
        const Vec2 g = relief.gradient(rng.uniform(), rng.uniform());
        const NormalAngles a = anglesOf(glm::normalize(Vec3(-g.x, -g.y, 1.0f)));
        const NormalAngles m = t.redistribution.toVisible(h.thetaV(k), {a.thetaN, a.phi - 2 * kPi * rng.uniform()});
        observed[h.thetaNBin(m.thetaN)] += 1.0;
      }
      for (int i = 0; i < 96; ++i)
        for (int j = 0; j < 32; ++j) expected[i] += h.mass(k, i, j) * kSamples;
      const testing::ChiSquareResult r = testing::chiSquareTest(observed, expected);
      EXPECT_GT(r.pValue, alpha) << "variant " << static_cast<int>(variant) << " slice " << k << " chi2 " << r.chi2;
      if (r.pValue <= alpha) testing::dumpTable(observed, expected);
    }
  }
}

}  // namespace
}  // namespace meso
