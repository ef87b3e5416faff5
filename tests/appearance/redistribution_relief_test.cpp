// Redistribution on real reliefs: Blinn normals sampled uniformly over the tile and mapped by
// R_theta follow the traced visible-normal distribution distr[theta] (chi-square, alpha 0.01 with
// Sidak correction over the tested slices and variants).
#include "meso/appearance/level_tables.h"

#include "meso/core/rng.h"
#include "support/chi_square.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace meso {
namespace {

struct Bumps : PeriodicRelief {
  float height(float x, float y) const override {
    return 0.06f *
           (std::sin(2 * kPi * x) * std::sin(2 * kPi * y) + 0.4f * std::cos(2 * kPi * (x + 2 * y)));
  }
  Vec2 gradient(float x, float y) const override {
    const float c = 0.06f * 2 * kPi;
    return {c * (std::cos(2 * kPi * x) * std::sin(2 * kPi * y) -
                 0.4f * std::sin(2 * kPi * (x + 2 * y))),
            c * (std::sin(2 * kPi * x) * std::cos(2 * kPi * y) -
                 0.8f * std::sin(2 * kPi * (x + 2 * y)))};
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
        const NormalAngles m =
            t.redistribution.toVisible(h.thetaV(k), {a.thetaN, a.phi - 2 * kPi * rng.uniform()});
        observed[h.thetaNBin(m.thetaN)] += 1.0;
      }
      for (int i = 0; i < 96; ++i)
        for (int j = 0; j < 32; ++j) expected[i] += h.mass(k, i, j) * kSamples;
      const testing::ChiSquareResult r = testing::chiSquareTest(observed, expected);
      EXPECT_GT(r.pValue, alpha) << "variant " << static_cast<int>(variant) << " slice " << k
                                 << " chi2 " << r.chi2;
      if (r.pValue <= alpha) testing::dumpTable(observed, expected);
    }
  }
}

// R_theta is continuous: an input normal moved by 1e-3 degrees moves the output by far less than
// 0.5 degrees, for both variants, at view angles up to 85 degrees. Half of the steps cross a
// phi-bin edge of the input, where the conditional maps of the paper's bins used to jump (by 4.7
// / 12.3 / 31.4 degrees at theta_V = 30 / 60 / 80 on this relief).
TEST(RedistributionOnRelief, MapsAreContinuous) {
  const Bumps relief;
  TableSettings settings;
  settings.histogram.resolution = {16, 96, 32};
  settings.histogram.raysPerView = 1024;
  const TableCache none{std::filesystem::path()};
  for (auto variant : {RedistributionVariant::Separable, RedistributionVariant::Conditional}) {
    settings.variant = variant;
    const LevelTables t = buildLevelTables(relief, 20.0f, settings, nullptr, none, nullptr);
    const float phiWidth = t.distr.phiWidth();
    Rng rng(77);
    float worst = 0.0f;
    constexpr int kSamples = 100000;
    for (int n = 0; n < kSamples; ++n) {
      const float thetaV = radians(85.0f) * rng.uniform();
      const Vec2 g = relief.gradient(rng.uniform(), rng.uniform());
      NormalAngles a = anglesOf(glm::normalize(Vec3(-g.x, -g.y, 1.0f)));
      a.phi = n % 2 ? -kPi + phiWidth * std::floor(32.0f * rng.uniform()) - radians(5e-4f) : a.phi;
      const Vec3 na = normalOf(a);
      // A step of 1e-3 degrees: rotate towards a random tangent direction (across phi for the
      // edge-crossing half).
      const Vec3 across = glm::normalize(Vec3(-std::sin(a.phi), std::cos(a.phi), 0.0f));
      const Vec3 random = glm::normalize(
          glm::cross(na, Vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f)));
      const Vec3 dir = n % 2 ? glm::normalize(across - glm::dot(across, na) * na) : random;
      const float step = radians(1e-3f);
      const NormalAngles b = anglesOf(glm::normalize(std::cos(step) * na + std::sin(step) * dir));
      const Vec3 oa = normalOf(t.redistribution.toVisible(thetaV, a));
      const Vec3 ob = normalOf(t.redistribution.toVisible(thetaV, b));
      const float d = std::acos(std::clamp(glm::dot(oa, ob), -1.0f, 1.0f));
      worst = std::max(worst, d);
    }
    EXPECT_LT(degrees(worst), 0.5f) << "variant " << static_cast<int>(variant);
    std::printf("variant %d: largest output step %.4f degrees\n", static_cast<int>(variant),
                degrees(worst));
  }
}

}  // namespace
}  // namespace meso
