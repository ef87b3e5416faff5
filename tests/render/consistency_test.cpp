// The paper's Figure 6 as a test, on two reliefs generated here: redistribution, BRDF and
// displacement agree pairwise; plain bump mapping does not at 60 and 80 degrees.
#include "meso/render/consistency.h"

#include "meso/core/rng.h"
#include "support/waves.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

namespace meso {
namespace {

// A sum of random periodic sinusoids (integer frequencies 1..3 so it tiles).
Waves randomWaves(uint64_t seed, float amplitude) {
  return meso::randomWaves(seed, amplitude, 6, 1, 3, -1, 4);
}

// Egg-crate bumps: |sin| products, sharper ridges than sinusoids.
struct EggCrate : PeriodicRelief {
  float a;
  explicit EggCrate(float amplitude) : a(amplitude) {}
  float height(float x, float y) const override {
    const float s = std::sin(2 * kPi * x) * std::sin(2 * kPi * y);
    return a * s * s;
  }
  Vec2 gradient(float x, float y) const override {
    const float sx = std::sin(2 * kPi * x), sy = std::sin(2 * kPi * y);
    const float cx = std::cos(2 * kPi * x), cy = std::cos(2 * kPi * y);
    return {a * 2 * sx * sy * sy * 2 * kPi * cx, a * 2 * sy * sx * sx * 2 * kPi * cy};
  }
  uint64_t fingerprint() const override { return 99; }
};

void expectConsistent(const PeriodicRelief& relief, const char* name) {
  const TableSettings settings;  // default: conditional redistribution
  const TableCache noCache{std::filesystem::path()};
  const LevelTables tables = buildLevelTables(relief, 20.0f, settings, nullptr, noCache, nullptr);
  const PeriodicTile tile(relief, 192);
  ConsistencySettings s;
  s.azimuths = 32;
  s.samplesPerAzimuth = 4096;
  for (float deg : {0.0f, 30.0f, 60.0f, 80.0f}) {
    const ConsistencyRow r = measureConsistency(relief, tile, tables, radians(deg), s);
    const double values[3] = {r.redistribution, r.brdf, r.displacement};
    for (int i = 0; i < 3; ++i) {
      ASSERT_TRUE(std::isfinite(values[i]));
      for (int j = i + 1; j < 3; ++j)
        EXPECT_LT(std::abs(values[i] - values[j]) / values[j], 0.015)
            << name << " at " << deg << " deg: redistribution " << r.redistribution << " brdf "
            << r.brdf << " displacement " << r.displacement;
    }
    if (deg >= 60.0f) {
      EXPECT_GT(std::abs(r.bump - r.displacement) / r.displacement, 0.05)
          << name << " at " << deg << " deg: bump " << r.bump << " displacement " << r.displacement;
    }
  }
}

// With relief self-shadowing (DESIGN.md section 6): displacement with a real shadow ray at every
// visible hit, redistribution and the BRDF with the traced shadowing factor, agree pairwise; and
// the shadows are not negligible (without them the displaced relief is clearly brighter).
void expectConsistentShadows(const PeriodicRelief& relief, const char* name, float thetaLDeg,
                             float phiDeg) {
  TableSettings settings;
  settings.shadows = true;
  const TableCache noCache{std::filesystem::path()};
  const LevelTables tables = buildLevelTables(relief, 20.0f, settings, nullptr, noCache, nullptr);
  ASSERT_FALSE(tables.shadowing.empty());
  const PeriodicTile tile(relief, 192);
  ConsistencySettings s;
  s.azimuths = 16;
  s.samplesPerAzimuth = 4096;
  s.thetaL = radians(thetaLDeg);
  s.phi = radians(phiDeg);
  for (float deg : {0.0f, 30.0f, 60.0f}) {
    s.shadows = true;
    const ConsistencyRow r = measureConsistency(relief, tile, tables, radians(deg), s);
    s.shadows = false;
    const ConsistencyRow unshadowed = measureConsistency(relief, tile, tables, radians(deg), s);
    const double values[3] = {r.redistribution, r.brdf, r.displacement};
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j)
        EXPECT_LT(std::abs(values[i] - values[j]) / values[j], 0.015)
            << name << " at theta_V " << deg << ": redistribution " << r.redistribution << " brdf "
            << r.brdf << " displacement " << r.displacement;
    EXPECT_GT(unshadowed.displacement / r.displacement, 1.04) << name << " at theta_V " << deg;
    EXPECT_GT(unshadowed.brdf / r.brdf, 1.04) << name << " at theta_V " << deg;
  }
}

TEST(Consistency, EggCrateAgreesWithShadows) {
  expectConsistentShadows(EggCrate(0.25f), "egg crate", 70.0f, 90.0f);
}

TEST(Consistency, RandomWavesAgree) { expectConsistent(randomWaves(5, 0.03f), "random waves"); }
TEST(Consistency, EggCrateAgrees) { expectConsistent(EggCrate(0.25f), "egg crate"); }

}  // namespace
}  // namespace meso
