// Solid (3-D) gradient noise: analytic gradients, periodic lattices and slices, bounds, and the
// homogeneity that lets one table set serve surfaces of every orientation.
#include "meso/relief/solid_noise.h"

#include "meso/core/error.h"
#include "meso/core/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace meso {
namespace {

// Fourth-order central differences along each axis (see fractal_noise_test.cpp for the step).
Vec3 finiteDifference(const SolidNoise& n, Vec3 p, float e) {
  Vec3 g;
  for (int k = 0; k < 3; ++k) {
    Vec3 s(0.0f);
    s[k] = e;
    g[k] = (8.0f * (n.height(p + s) - n.height(p - s)) -
            (n.height(p + 2.0f * s) - n.height(p - 2.0f * s))) /
           (12.0f * e);
  }
  return g;
}

TEST(SolidNoise, AnalyticGradientMatchesFiniteDifferences) {
  for (bool periodic : {false, true}) {
    SolidNoiseOptions o;
    o.octaves = 4;
    o.seed = 5;
    o.periodic = periodic;
    const SolidNoise n(o);
    Rng rng(3);
    double worst = 0.0, rms = 0.0;
    for (int k = 0; k < 400; ++k) {
      const Vec3 p = 6.0f * Vec3(rng.uniform(), rng.uniform(), rng.uniform());
      Vec3 g;
      const float h = n.heightAndGradient(p, g);
      EXPECT_EQ(h, n.height(p));
      EXPECT_EQ(g, n.gradient(p));
      worst = std::max(worst,
                       static_cast<double>(glm::length(finiteDifference(n, p, 1.0f / 4096) - g)));
      rms += glm::dot(g, g) / 400.0;
    }
    // The gradient is of order 1 to 10 (8 cells per unit at the last octave): an error in the
    // chain rule (the rotation, a frequency factor) would be of that order.
    EXPECT_GT(std::sqrt(rms), 1.0);
    EXPECT_LT(worst, 2e-2) << "periodic " << periodic;
  }
}

TEST(SolidNoise, PeriodicLatticeRepeatsAlongEachAxisAndTheRendererNoiseDoesNot) {
  SolidNoiseOptions o;
  o.octaves = 3;
  o.seed = 11;
  o.periodic = true;
  o.period = 6;
  const SolidNoise periodic(o);
  o.periodic = false;
  const SolidNoise free(o);
  Rng rng(4);
  double differs = 0.0, half = 0.0;  // half: no shorter period
  for (int k = 0; k < 200; ++k) {
    const Vec3 p = Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 2.0f - 1.0f;
    for (int axis = 0; axis < 3; ++axis) {
      Vec3 shift(0.0f);
      shift[axis] = 6.0f;
      EXPECT_NEAR(periodic.height(p + shift), periodic.height(p), 1e-5f);
      differs += std::abs(free.height(p + shift) - free.height(p));
      half += std::abs(periodic.height(p + 0.5f * shift) - periodic.height(p));
    }
  }
  EXPECT_GT(differs / 600.0, 0.05);
  EXPECT_GT(half / 600.0, 0.05);
}

TEST(SolidNoise, SliceTilesAndIsTheNoiseOnItsPlane) {
  SolidNoiseOptions o;
  o.octaves = 4;
  o.seed = 2;
  const SolidSlice slice(o);
  o.periodic = true;
  const SolidNoise noise(o);
  Rng rng(6);
  for (int k = 0; k < 200; ++k) {
    const Vec2 p(rng.uniform(), rng.uniform());
    EXPECT_NEAR(slice.height(p + Vec2(1.0f, 0.0f)), slice.height(p), 1e-4f);
    EXPECT_NEAR(slice.height(p + Vec2(0.0f, 1.0f)), slice.height(p), 1e-4f);
    EXPECT_FLOAT_EQ(slice.height(p), noise.height(Vec3(6.0f * p, 0.0f)));
    // The slice's gradient per unit of tile is side times the noise's along the plane.
    const Vec3 g = noise.gradient(Vec3(6.0f * p, 0.0f));
    const Vec2 gs = slice.gradient(p);
    EXPECT_NEAR(gs.x, 6.0f * g.x, 1e-3f * (1.0f + std::abs(gs.x)));
    EXPECT_NEAR(gs.y, 6.0f * g.y, 1e-3f * (1.0f + std::abs(gs.y)));
  }
  EXPECT_FLOAT_EQ(slice.highestFrequency(), 6.0f * 8.0f);
  EXPECT_FLOAT_EQ(slice.lowestFrequency(), 6.0f * 1.0f);  // octaves of 1, 2, 4 and 8 cells
  // A tilted tile whose axes are periods: (1, 2, 2) / 3 and (2, 1, -2) / 3 times 18.
  const SolidSlice tilted(o, Vec3(1, 2, 2) / 3.0f, Vec3(2, 1, -2) / 3.0f, 18.0f);
  for (int k = 0; k < 50; ++k) {
    const Vec2 p(rng.uniform(), rng.uniform());
    EXPECT_NEAR(tilted.height(p + Vec2(1.0f, 0.0f)), tilted.height(p), 2e-4f);
  }
  EXPECT_THROW(SolidSlice(o, Vec3(1, 0, 0), Vec3(0, 1, 0), 3.0f), Error);
  EXPECT_THROW(SolidSlice(o, Vec3(1, 0, 0), Vec3(1, 0, 0)), Error);
}

// The tables' tile: as many cells as keep the finest octave at 48 cycles or fewer.
TEST(SolidNoise, TilePeriodFollowsTheFinestOctave) {
  SolidNoiseOptions o;
  for (auto [octaves, period] : {std::pair{1, 48}, {2, 24}, {3, 12}, {4, 6}, {5, 3}, {7, 3}}) {
    o.octaves = octaves;
    EXPECT_EQ(solidTilePeriod(o), period) << octaves;
    o.periodic = true;
    EXPECT_EQ(SolidNoise(o).period(), period);
    EXPECT_FLOAT_EQ(SolidSlice(o).side(), static_cast<float>(period));
  }
  o.octaves = 2;
  o.firstOctave = 1;  // the second octave alone
  EXPECT_EQ(solidTilePeriod(o), 24);
  o.period = 4;
  EXPECT_THROW(SolidNoise{o}, Error);
}

TEST(SolidNoise, BoundHoldsAndIsNotVacuous) {
  SolidNoiseOptions o;
  o.octaves = 1;
  const SolidNoise n(o);
  Rng rng(8);
  float top = 0.0f;
  for (int k = 0; k < 200000; ++k) {
    const float h = std::abs(n.height(20.0f * Vec3(rng.uniform(), rng.uniform(), rng.uniform())));
    ASSERT_LE(h, n.maxAbsHeight());
    top = std::max(top, h);
  }
  EXPECT_GT(top, 0.5f * n.maxAbsHeight());
}

TEST(SolidNoise, SplitOctavesAddUpToTheWholeSum) {
  SolidNoiseOptions o;
  o.octaves = 3;
  o.seed = 9;
  const SolidNoise whole(o);
  Rng rng(10);
  for (int k = 0; k < 100; ++k) {
    const Vec3 p = 4.0f * Vec3(rng.uniform(), rng.uniform(), rng.uniform());
    float sum = 0.0f;
    for (int first = 0; first < 3; ++first) {
      SolidNoiseOptions one = o;
      one.firstOctave = first;
      one.octaves = first + 1;
      sum += SolidNoise(one).height(p);
    }
    EXPECT_NEAR(sum, whole.height(p), 1e-5f);
  }
}

// The mean square of the noise's gradient projected on the plane with unit normal m through the
// point c, over a 128 x 128 cell patch of it.
double planeSlopeMeanSquare(const SolidNoise& n, Vec3 m, Vec3 c) {
  const Vec3 a =
      glm::normalize(glm::cross(m, std::abs(m.x) < 0.9f ? Vec3(1, 0, 0) : Vec3(0, 1, 0)));
  const Vec3 b = glm::cross(m, a);
  double sum = 0.0;
  constexpr int kSide = 1024;
  for (int i = 0; i < kSide; ++i)
    for (int j = 0; j < kSide; ++j) {
      const Vec3 p = c + (128.0f * (static_cast<float>(i) + 0.5f) / kSide) * a +
                     (128.0f * (static_cast<float>(j) + 0.5f) / kSide) * b;
      const Vec3 g = n.gradient(p);
      const Vec3 t = g - glm::dot(g, m) * m;
      sum += glm::dot(t, t);
    }
  return sum / (kSide * kSide);
}

// Gradient noise is not homogeneous: on a lattice plane its slopes differ from those between. The
// turned lattice keeps the planes that surfaces are made of (along the axes: grounds, walls, cube
// faces) off the lattice planes, so they see the same slopes as the tables' slice and as oblique
// planes.
TEST(SolidNoise, PlanesOfEveryOrientationSeeTheSameSlopes) {
  SolidNoiseOptions o;
  o.octaves = 1;
  o.seed = 1;
  const SolidNoise n(o);
  const Vec3 normals[] = {{0, 0, 1},
                          {1, 0, 0},
                          {0, 1, 0},
                          glm::normalize(Vec3(1, 1, 0)),
                          glm::normalize(Vec3(1, 1, 1)),
                          glm::normalize(Vec3(0.3f, -0.7f, 0.2f))};
  std::vector<double> values;
  for (const Vec3& m : normals)
    for (float offset : {0.0f, 0.37f}) values.push_back(planeSlopeMeanSquare(n, m, Vec3(offset)));
  double reference = 0.0;
  for (double v : values) reference += v / static_cast<double>(values.size());
  for (size_t k = 0; k < values.size(); ++k) {
    EXPECT_NEAR(values[k] / reference, 1.0, 0.03) << "plane " << k / 2 << " offset " << k % 2;
  }
  // Control: planes along the lattice (normal Q e_z, a row of the rotation) see other slopes at
  // some of their offsets.
  const Vec3 lattice = Vec3(2, -2, 1) / 3.0f;
  double worst = 0.0;
  for (int k = 0; k < 8; ++k)
    worst = std::max(
        worst, std::abs(planeSlopeMeanSquare(n, lattice, (k / 8.0f) * lattice) / reference - 1.0));
  EXPECT_GT(worst, 0.05);
}

}  // namespace
}  // namespace meso
