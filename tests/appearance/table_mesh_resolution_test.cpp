// The tables trace a height image's tile finely enough to resolve its interpolated surface
// (tableMeshResolution, relief_level.h).
#include "meso/appearance/material_tables.h"
#include "meso/appearance/periodic_tile.h"
#include "meso/core/rng.h"
#include "meso/relief/fractal_noise.h"
#include "meso/relief/height_table.h"
#include "meso/relief/relief_level.h"

#include <gtest/gtest.h>

#include <cmath>

namespace meso {
namespace {

// A sharp 32 x 32 image: texels of random height 0 or 1 (mortar-like steps at the texel scale).
ReliefLevel sharpImage() {
  Rng rng(7);
  std::vector<float> texels(32 * 32);
  for (float& t : texels) t = rng.uniform() < 0.5f ? 0.0f : 1.0f;
  ReliefLevel level;
  level.source = std::make_unique<HeightTable>(32, 32, std::move(texels));
  level.amplitude = 0.02f;
  level.freqPerU = level.source->highestFrequency();
  return level;
}

// Mean height of the surface seen along rays at 80 degrees from the normal, on a fixed grid of
// ray origins: grazing rays see only the tops, and how much of the valleys they see depends on
// how faithfully the traced mesh follows the bilinear surface between texels.
double grazingVisibleHeight(const PeriodicRelief& relief, int meshResolution) {
  const PeriodicTile tile(relief, meshResolution);
  const float theta = 80.0f * 3.14159265f / 180.0f;
  const Vec3 d(-std::sin(theta) * 0.8f, -std::sin(theta) * 0.6f, -std::cos(theta));
  double sum = 0.0;
  int hits = 0;
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) {
      Vec3 hit;
      if (!tile.traceHit(Vec3((i + 0.37f) / 64.0f, (j + 0.71f) / 64.0f, 10.0f), d, hit)) continue;
      sum += hit.z;
      ++hits;
    }
  return hits > 0 ? sum / hits : 0.0;
}

TEST(TableMeshResolution, HeightImagesAreTracedAtTwoQuadsPerTexelNoiseAtTheBase) {
  const ReliefLevel image = sharpImage();
  EXPECT_EQ(tableMeshResolution(image, 24), 64);    // 2 per texel
  EXPECT_EQ(tableMeshResolution(image, 192), 192);  // never below the base
  ReliefLevel big = sharpImage();
  big.source = std::make_unique<HeightTable>(2048, 2048, std::vector<float>(2048 * 2048, 0.5f));
  EXPECT_EQ(tableMeshResolution(big, 192), 192);  // flat: no energy to resolve
  ReliefLevel noise;
  noise.source = std::make_unique<FractalNoise>(FractalNoiseOptions{});
  EXPECT_EQ(tableMeshResolution(noise, 192), 192);
}

// Traced at the chosen resolution the grazing view agrees with a mesh four times finer; traced
// below the texels (the control) it does not.
TEST(TableMeshResolution, ChosenResolutionResolvesTheGrazingView) {
  const ReliefLevel image = sharpImage();
  const TileRelief relief(image);
  const double fine = grazingVisibleHeight(relief, 256);
  const double chosen = grazingVisibleHeight(relief, tableMeshResolution(image, 24));
  const double coarse = grazingVisibleHeight(relief, 24);
  const double range = 0.02;  // amplitude: the tile's height range
  // Measured: 0.01% and 13% of the range.
  EXPECT_LT(std::abs(chosen - fine), 0.005 * range) << chosen << " vs " << fine;
  EXPECT_GT(std::abs(coarse - fine), 0.05 * range) << coarse << " vs " << fine;
}

}  // namespace
}  // namespace meso
