// The DFT of any length against the definition, and the measured highest frequency.
#include "meso/relief/fourier.h"
#include "meso/core/rng.h"
#include "meso/relief/highest_frequency.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace meso {
namespace {

TEST(Dft, MatchesTheDefinitionForAnyLength) {
  Rng rng(1);
  for (size_t n : {1u, 2u, 3u, 5u, 8u, 12u, 17u, 64u, 100u}) {
    std::vector<Complex> x(n);
    for (Complex& c : x) c = Complex(rng.uniform() - 0.5, rng.uniform() - 0.5);
    std::vector<Complex> X = x;
    const Dft dft(n);
    dft.forward(X);
    ASSERT_EQ(X.size(), n);
    for (size_t k = 0; k < n; ++k) {
      Complex expected(0.0);
      for (size_t j = 0; j < n; ++j)
        expected += x[j] * std::polar(1.0, -2.0 * std::numbers::pi * double(j * k % n) / n);
      EXPECT_LT(std::abs(X[k] - expected), 1e-10 * n) << n << " " << k;
    }
    dft.inverse(X);
    for (size_t j = 0; j < n; ++j) EXPECT_LT(std::abs(X[j] - x[j]), 1e-12 * n);
  }
}

TEST(HighestFrequency, FindsTheHighestSignificantFrequency) {
  for (int n : {64, 90}) {  // radix-2 and Bluestein
    std::vector<float> t(static_cast<size_t>(n) * n);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        t[j * n + i] = std::sin(2 * kPi * 3 * i / n) + 0.3f * std::sin(2 * kPi * 11 * i / n) +
                       std::cos(2 * kPi * 7 * j / n);
    const Vec2 f = highestFrequencies(t.data(), n, n, true, 1e-3f);
    EXPECT_EQ(f, Vec2(11.0f, 7.0f)) << n;
    // A 10% cut leaves out the weak 11-cycle wave (8% of the energy along x).
    EXPECT_EQ(highestFrequencies(t.data(), n, n, true, 0.1f).x, 3.0f);
  }
  Rng rng(6);
  std::vector<float> noise(128 * 64);
  for (float& v : noise) v = rng.uniform();
  const Vec2 f = highestFrequencies(noise.data(), 128, 64, true, 1e-3f);
  EXPECT_GE(f.x, 63.0f);  // white noise reaches Nyquist
  EXPECT_GE(f.y, 31.0f);
  std::vector<float> flat(16, 1.0f);
  EXPECT_EQ(highestFrequencies(flat.data(), 4, 4, true, 1e-3f), Vec2(0.0f));
  // A non-periodic ramp: the window keeps the wrap-around jump from counting as detail.
  std::vector<float> ramp(64 * 8);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 64; ++i) ramp[j * 64 + i] = i / 64.0f;
  EXPECT_LE(highestFrequencies(ramp.data(), 64, 8, false, 1e-3f).x, 4.0f);
  EXPECT_GE(highestFrequencies(ramp.data(), 64, 8, true, 1e-3f).x, 16.0f);
}

}  // namespace
}  // namespace meso
