// Local contrast (DESIGN.md section 6): exact values on synthetic images, flat regions that show no
// relief, an image with the reference's mean but no texture failing the detail check, and sampling
// noise (two seeds) kept from counting as detail.
#include "meso/render/local_contrast.h"

#include "meso/core/math.h"
#include "meso/core/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

namespace meso {
namespace {

constexpr int kSize = 128;  // 16 x 16 blocks

LuminanceImage image(const std::function<double(int, int)>& f) {
  LuminanceImage im{kSize, kSize, std::vector<float>(kSize * kSize), {}};
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) im.y[y * kSize + x] = static_cast<float>(f(x, y));
  return im;
}

// Gaussian noise of standard deviation sigma (Box-Muller), one stream per seed.
std::vector<float> noise(uint64_t seed, double sigma) {
  Rng rng(seed);
  std::vector<float> n(kSize * kSize);
  for (float& v : n) {
    const double u1 = 1.0 - rng.uniform(), u2 = rng.uniform();
    v = static_cast<float>(sigma * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2));
  }
  return n;
}

// The sums of the whole image as one region.
ContrastSums whole(const LuminanceImage& im) {
  std::vector<ContrastSums> sums(1);
  addContrastBlocks(im, std::vector<int>(im.y.size(), 0), sums);
  return sums[0];
}

double checker(int x, int y) { return (x + y) % 2 == 0 ? 1.0 : -1.0; }

// A checkerboard of amplitude A about mu: every block's residual is A^2, so C = A / mu exactly; a
// ramp under it is the block's plane and changes nothing; a ramp alone is shading, not texture.
TEST(LocalContrast, KnownValuesOfSyntheticImages) {
  const ContrastSums c = whole(image([](int x, int y) { return 0.5 + 0.1 * checker(x, y); }));
  EXPECT_EQ(c.blocks, 16 * 16);
  EXPECT_NEAR(c.contrast(), 0.2, 1e-6);
  EXPECT_NEAR(c.rawContrast(), 0.2, 1e-6);
  EXPECT_EQ(c.relativeNoise(), 0.0);  // no second seed: no noise correction
  const ContrastSums ramp =
      whole(image([](int x, int y) { return 0.2 + 0.002 * x + 0.001 * y + 0.05 * checker(x, y); }));
  const double rampMean = 0.2 + 0.002 * 63.5 + 0.001 * 63.5;
  EXPECT_NEAR(ramp.contrast(), 0.05 / rampMean, 1e-5);
  const ContrastSums stripes =
      whole(image([](int x, int) { return 0.4 + (x % 2 ? 0.02 : -0.02); }));
  // Stripes correlate a little with x over 8 pixels (sum (-1)^x x' = 4): the plane takes
  // 4^2 / (8 x 63 / 12) / 8 = 1/21 of their variance.
  EXPECT_NEAR(stripes.contrast(), 0.05 * std::sqrt(20.0 / 21.0), 1e-5);
  EXPECT_NEAR(whole(image([](int x, int y) { return 0.1 + 0.003 * x + 0.002 * y; })).contrast(),
              0.0, 1e-4);
}

// Only blocks wholly inside one region count: the left half labelled 0, the right half 1, a
// strip of -1 (no region) and a block across the border counts for neither.
TEST(LocalContrast, BlocksWhollyInsideTheirRegion) {
  const LuminanceImage im = image(
      [](int x, int y) { return x < 60 ? 0.5 + 0.1 * checker(x, y) : 0.5 + 0.2 * checker(x, y); });
  std::vector<int> label(im.y.size());
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) label[y * kSize + x] = y < 8 ? -1 : (x < 60 ? 0 : 1);
  std::vector<ContrastSums> sums(2);
  addContrastBlocks(im, label, sums);
  EXPECT_EQ(sums[0].blocks, 7 * 15);  // x 0..55 in 7 blocks; block 56..63 straddles
  EXPECT_EQ(sums[1].blocks, 8 * 15);
  EXPECT_NEAR(sums[0].contrast(), 0.2, 1e-6);
  EXPECT_NEAR(sums[1].contrast(), 0.4, 1e-6);
}

// A flat region has no contrast and shows no relief: any image passes there.
TEST(LocalContrast, FlatRegionShowsNoRelief) {
  const ContrastSums flat = whole(image([](int, int) { return 0.3; }));
  EXPECT_EQ(flat.contrast(), 0.0);
  const ContrastSums textured =
      whole(image([](int x, int y) { return 0.3 + 0.1 * checker(x, y); }));
  EXPECT_TRUE(std::isnan(contrastRatio(textured, flat)));
  EXPECT_TRUE(asDetailed(contrastRatio(textured, flat)));
  // Just below the floor is no relief either.
  const double a = 0.3 * 0.99 * kReliefContrastFloor;
  const ContrastSums faint = whole(image([a](int x, int y) { return 0.3 + a * checker(x, y); }));
  EXPECT_TRUE(std::isnan(contrastRatio(flat, faint)));
}

// The reference's mean with its texture erased (what a BRDF does to visible relief) fails; the
// reference itself passes, and so does 5% less texture; 15% less fails.
TEST(LocalContrast, SameMeanWithoutTextureFails) {
  const ContrastSums reference =
      whole(image([](int x, int y) { return 0.5 + 0.05 * checker(x, y); }));
  const ContrastSums erased = whole(image([](int, int) { return 0.5; }));
  EXPECT_NEAR(erased.mean / erased.blocks, reference.mean / reference.blocks, 1e-9);
  EXPECT_EQ(contrastRatio(erased, reference), 0.0);
  EXPECT_FALSE(asDetailed(contrastRatio(erased, reference)));
  EXPECT_NEAR(contrastRatio(reference, reference), 1.0, 1e-12);
  EXPECT_TRUE(asDetailed(contrastRatio(reference, reference)));
  const auto scaled = [](double f) {
    return whole(image([f](int x, int y) { return 0.5 + f * 0.05 * checker(x, y); }));
  };
  EXPECT_TRUE(asDetailed(contrastRatio(scaled(0.95), reference)));
  EXPECT_TRUE(asDetailed(contrastRatio(scaled(1.08), reference)));
  EXPECT_FALSE(asDetailed(contrastRatio(scaled(0.85), reference)));
  EXPECT_FALSE(asDetailed(contrastRatio(scaled(1.15), reference)));
}

// Sampling noise: a flat image with 5% Gaussian noise reads as a contrast of about 0.05 without
// correction; with a second seed it reads below 0.2 x 0.05 (the documented bound for 256 blocks,
// three standard deviations) and shows no relief. Texture under the same noise keeps its contrast.
TEST(LocalContrast, SecondSeedKeepsNoiseFromCountingAsDetail) {
  const double sigma = 0.05 * 0.5;
  for (uint64_t seed = 1; seed <= 8; ++seed) {
    const std::vector<float> a = noise(seed, sigma), b = noise(secondSeed(seed), sigma);
    LuminanceImage flat = image([&](int x, int y) { return 0.5 + a[y * kSize + x]; });
    EXPECT_NEAR(whole(flat).rawContrast(), 0.05 * std::sqrt(61.0 / 64.0), 0.003);
    flat.ySecond = image([&](int x, int y) { return 0.5 + b[y * kSize + x]; }).y;
    const ContrastSums corrected = whole(flat);
    EXPECT_NEAR(corrected.relativeNoise(), 0.05, 0.003);
    EXPECT_LT(corrected.contrast(), 0.2 * 0.05) << "seed " << seed;
    EXPECT_LT(corrected.contrast(), kReliefContrastFloor);

    LuminanceImage textured =
        image([&](int x, int y) { return 0.5 + 0.025 * checker(x, y) + a[y * kSize + x]; });
    textured.ySecond =
        image([&](int x, int y) { return 0.5 + 0.025 * checker(x, y) + b[y * kSize + x]; }).y;
    EXPECT_NEAR(whole(textured).contrast() / 0.05, 1.0, 0.05) << "seed " << seed;
  }
}

}  // namespace
}  // namespace meso
