// Fractal gradient noise: analytic gradients, tiling, determinism.
#include "meso/relief/fractal_noise.h"
#include "meso/core/error.h"
#include "meso/core/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

namespace meso {
namespace {

// Fourth-order central differences. The quintic fade makes the noise C2 only, so near cell edges
// the truncation error is O(e^2); rounding of h grows as 1 / e: e = 2^-13 balances the two.
Vec2 finiteDifference(const FractalNoise& n, Vec2 p, float e) {
  const auto d = [&](Vec2 s) {
    return (8.0f * (n.height(p + s) - n.height(p - s)) -
            (n.height(p + 2.0f * s) - n.height(p - 2.0f * s))) /
           (12.0f * e);
  };
  return {d(Vec2(e, 0)), d(Vec2(0, e))};
}

TEST(FractalNoise, AnalyticGradientMatchesFiniteDifferences) {
  for (bool periodic : {true, false}) {
    FractalNoiseOptions o;
    o.octaves = 5;
    o.lacunarity = periodic ? 2.0f : 2.17f;
    o.seed = 7;
    o.periodic = periodic;
    const FractalNoise n(o);
    Rng rng(9);
    double worst = 0.0, rms = 0.0;
    for (int k = 0; k < 500; ++k) {
      const Vec2 p(rng.uniform(), rng.uniform());
      const Vec2 g = n.gradient(p), fd = finiteDifference(n, p, 1.0f / 8192);
      worst = std::max(worst, static_cast<double>(glm::length(fd - g)));
      rms += glm::dot(g, g) / 500.0;
      Vec2 g2;
      EXPECT_EQ(n.heightAndGradient(p, g2), n.height(p));
      EXPECT_EQ(g2, g);
    }
    // Relative to the gradient's RMS (measured: 3.5e-4 at 2^-13, 4x more per doubling of e).
    worst /= std::sqrt(rms);
    EXPECT_LT(worst, 1e-3) << "periodic " << periodic;
  }
}

// The analytic second derivative along a direction against central differences of the analytic
// gradient (exact by the test above). Inside the lattice cells of every octave the difference's
// error falls as e^2. The noise is C2 but its third derivative jumps on lattice lines: at points on
// them the error falls as e, and stays small only if the second derivative is continuous there. A
// wrong Hessian term is off by a fixed amount and fails both.
TEST(FractalNoise, SecondDerivativeAlongADirectionMatchesTheGradientsDifferences) {
  for (bool periodic : {true, false}) {
    FractalNoiseOptions o;
    o.octaves = 4;
    o.lacunarity = periodic ? 2.0f : 2.17f;
    o.seed = 11;
    o.periodic = periodic;
    const FractalNoise n(o);
    std::vector<double> frequencies;  // as the constructor makes them (rounded when periodic)
    for (double f = o.baseFrequency; frequencies.size() < 4; f *= o.lacunarity)
      frequencies.push_back(periodic ? std::round(f) : f);
    const double e = 1.0 / (64.0 * frequencies.back());
    // Whether p + t dir, |t| <= e, stays in one cell of every octave.
    const auto insideCells = [&](Vec2 p, Vec2 dir) {
      for (double f : frequencies)
        for (int a = 0; a < 2; ++a) {
          const double lo = (p[a] - e * std::abs(dir[a])) * f,
                       hi = (p[a] + e * std::abs(dir[a])) * f;
          if (std::floor(lo) != std::floor(hi)) return false;
        }
      return true;
    };
    const auto differenced = [&](Vec2 p, Vec2 dir, double h) {
      const Vec2 step = static_cast<float>(h) * dir;
      return glm::dot(Vec2(n.gradient(p + step) - n.gradient(p - step)), dir) / (2.0 * h);
    };
    Rng rng(5);
    // Worst errors at e and e / 2: inside cells, and on the finest octave's lattice lines.
    double inCoarse = 0.0, inFine = 0.0, onCoarse = 0.0, onFine = 0.0, square = 0.0;
    int inside = 0, online = 0;
    for (int k = 0; k < 600; ++k) {
      Vec2 p(rng.uniform(), rng.uniform());
      const float angle = 6.2831853f * rng.uniform();
      const Vec2 dir = (0.5f + rng.uniform()) * Vec2(std::cos(angle), std::sin(angle));
      const bool onLine = k % 3 == 0;
      if (onLine)
        p.x = static_cast<float>(std::round(p.x * frequencies.back()) / frequencies.back());
      else if (!insideCells(p, dir))
        continue;
      const std::optional<float> d2 = n.secondDerivative(p, dir);
      ASSERT_TRUE(d2.has_value());
      ASSERT_TRUE(std::isfinite(*d2));
      const double coarse = std::abs(differenced(p, dir, e) - *d2);
      const double fine = std::abs(differenced(p, dir, e / 2.0) - *d2);
      (onLine ? onCoarse : inCoarse) = std::max(onLine ? onCoarse : inCoarse, coarse);
      (onLine ? onFine : inFine) = std::max(onLine ? onFine : inFine, fine);
      (onLine ? online : inside) += 1;
      square += static_cast<double>(*d2) * *d2;
    }
    ASSERT_GT(inside, 100);
    const double rms = std::sqrt(square / (inside + online));
    // Measured: inside 5.9e-3 and 3.3e-3 at e / 2 (ratio 4.0); on lines 0.19 and 0.15 (ratio 1.9).
    EXPECT_LT(inFine / rms, 0.012) << "periodic " << periodic;
    EXPECT_GT(inCoarse / inFine, 3.0) << "periodic " << periodic;
    EXPECT_LT(inCoarse / inFine, 5.0) << "periodic " << periodic;
    EXPECT_LT(onFine / rms, 0.3) << "periodic " << periodic;
    EXPECT_GT(onCoarse / onFine, 1.6) << "periodic " << periodic;
  }
}

// The table cache keys noise relief by FractalNoise::fingerprint ("FractalNoise/2"): tables built
// from these values are reused by later runs, so the noise must give them bit for bit until that
// version is raised. Values of heightAndGradient at points on and near lattice lines, negative, and
// beyond the 1e9 cells where the lattice wraps, for a periodic and a non-periodic noise.
TEST(FractalNoise, ValuesOfThisLatticeVersionStayTheSame) {
  const Vec2 points[] = {{0.25f, 0.75f},      {0.99999994f, 2.0f},       {-1e-8f, -0.5f},
                         {3.0f, -7.0000005f}, {12345.678f, -0.333f},     {4.7e7f, 1.5e8f},
                         {-2.9e9f, 0.1f},     {1.0f / 3.0f, 2.0f / 3.0f}};
  // {height, gradient} for the periodic noise, then for the other.
  const float expected[16][3] = {
      {0x1.417db6p-3, -0x1.869af4p+2, -0x1.64fa0ap+1},
      {0x1.32p-21, -0x1.c66008p+1, -0x1.00e3ap+1},
      {-0x1.f789eep-2, 0x1.e963c8p+1, 0x1.c7865cp-1},
      {0x1.dap-22, -0x1.c6602cp+1, -0x1.00e3ap+1},
      {0x1.fba21cp-7, 0x1.4f255ep+0, -0x1.228f5cp-1},
      {0x0p+0, -0x1.c66024p+1, -0x1.00e394p+1},
      {-0x1.2ad77cp-2, -0x1.14b338p+1, -0x1.950ea4p+0},
      {0x1.c8aff4p-4, -0x1.fff5ap+1, -0x1.006962p+2},
      {0x1.27cc8p-2, -0x1.0770dcp+2, 0x1.63dc8p-2},
      {-0x1.53d13cp-6, -0x1.97842cp-2, -0x1.29c02p-1},
      {-0x1.3e77ap-1, 0x1.d9862cp+1, 0x1.64bd1p+1},
      {0x1.31d0e4p-4, 0x1.b597ep+2, -0x1.5f022p-3},
      {0x1.96a7a4p-3, 0x1.ad4822p+2, 0x1.334d0cp+1},
      {0x1.b59f26p-3, 0x1.1e13acp+1, 0x1.fcc658p+0},
      {-0x1.068006p-3, 0x1.2f9db4p+1, 0x1.048f1p+1},
      {-0x1.e399c6p-4, -0x1.807b1p+1, -0x1.ac2008p-1},
  };
  int k = 0;
  for (bool periodic : {true, false}) {
    FractalNoiseOptions o;
    o.octaves = 4;
    o.baseFrequency = 3.0f;
    o.lacunarity = periodic ? 1.9f : 2.17f;
    o.seed = 11;
    o.periodic = periodic;
    const FractalNoise n(o);
    for (const Vec2& p : points) {
      Vec2 g;
      const float h = n.heightAndGradient(p, g);
      EXPECT_EQ(h, expected[k][0]) << "point " << k;
      EXPECT_EQ(g.x, expected[k][1]) << "point " << k;
      EXPECT_EQ(g.y, expected[k][2]) << "point " << k;
      ++k;
    }
  }
}

TEST(FractalNoise, PeriodicNoiseTiles) {
  FractalNoiseOptions o;
  o.baseFrequency = 3.0f;
  o.lacunarity = 1.9f;  // octaves get rounded cell counts 3, 6, 11, 21
  o.seed = 4;
  const FractalNoise n(o);
  Rng rng(1);
  for (int k = 0; k < 300; ++k) {
    // Dyadic points: p + 1 is exact, so tiling must hold bit for bit.
    const Vec2 p(std::ldexp(static_cast<float>(rng.nextU32() >> 20), -12),
                 std::ldexp(static_cast<float>(rng.nextU32() >> 20), -12));
    EXPECT_EQ(n.height(p), n.height(p + Vec2(1.0f, 0.0f)));
    EXPECT_EQ(n.height(p), n.height(p + Vec2(0.0f, 1.0f)));
    EXPECT_EQ(n.height(p), n.height(p - Vec2(3.0f, 2.0f)));
    EXPECT_EQ(n.gradient(p), n.gradient(p + Vec2(1.0f, -1.0f)));
    // Any point: equal to rounding of p + 1.
    const Vec2 q(rng.uniform(), rng.uniform());
    EXPECT_NEAR(n.height(q), n.height(q + Vec2(1.0f, 0.0f)), 1e-4f);
  }
  EXPECT_FLOAT_EQ(n.highestFrequency(), 21.0f);  // round(3 * 1.9^3)
  EXPECT_FLOAT_EQ(n.lowestFrequency(), 3.0f);    // the first octave
}

TEST(FractalNoise, LowestFrequencyIsTheFirstOctaveKept) {
  FractalNoiseOptions o;
  o.octaves = 3;
  const FractalNoise whole(o);
  EXPECT_FLOAT_EQ(whole.lowestFrequency(), 4.0f);
  EXPECT_FLOAT_EQ(whole.highestFrequency(), 16.0f);
  o.firstOctave = 1;
  const FractalNoise upper(o);
  EXPECT_FLOAT_EQ(upper.lowestFrequency(), 8.0f);
  EXPECT_FLOAT_EQ(upper.highestFrequency(), 16.0f);
}

TEST(FractalNoise, DeterministicPerSeed) {
  const FractalNoise a(4, 2.0f, 0.5f, 7), b(4, 2.0f, 0.5f, 7), c(4, 2.0f, 0.5f, 8);
  Rng rng(3);
  int differ = 0;
  for (int k = 0; k < 100; ++k) {
    const Vec2 p(rng.uniform(), rng.uniform());
    EXPECT_EQ(a.height(p), b.height(p));
    EXPECT_EQ(a.gradient(p), b.gradient(p));
    differ += a.height(p) != c.height(p);
  }
  EXPECT_GT(differ, 95);
  EXPECT_EQ(a.fingerprint(), b.fingerprint());
  EXPECT_NE(a.fingerprint(), c.fingerprint());
  EXPECT_FLOAT_EQ(a.highestFrequency(), 32.0f);  // 4 * 2^3
  FractalNoiseOptions o;
  o.periodic = false;
  o.baseFrequency = 2.5f;
  o.octaves = 3;
  o.lacunarity = 3.0f;
  EXPECT_FLOAT_EQ(FractalNoise(o).highestFrequency(), 22.5f);
}

TEST(FractalNoise, FiniteAndBounded) {
  const FractalNoise n(6, 2.0f, 0.5f, 1);
  for (float x : {-1e20f, -3.5f, 0.0f, 0.999999f, 1e7f, 1e20f, NAN, INFINITY}) {
    const float h = n.height({x, 0.3f});
    const Vec2 g = n.gradient({0.7f, x});
    EXPECT_TRUE(std::isfinite(h) && std::isfinite(g.x) && std::isfinite(g.y)) << x;
    EXPECT_LT(std::abs(h), 2.0f);
  }
}

}  // namespace
}  // namespace meso

namespace meso {
namespace {

// relief.split_octaves: the octaves of one fBm as separate sources add up to it, heights and
// gradients, up to the order of the float sums; each part has its octave's frequency, and its own
// fingerprint (so its tables are cached apart).
TEST(FractalNoise, OctaveRangesSumToTheWholeNoise) {
  FractalNoiseOptions whole;
  whole.octaves = 5;
  whole.seed = 13;
  const FractalNoise all(whole);
  std::vector<FractalNoise> parts;
  for (int o = 0; o < whole.octaves; ++o) {
    FractalNoiseOptions part = whole;
    part.firstOctave = o;
    part.octaves = o + 1;
    parts.emplace_back(part);
    EXPECT_FLOAT_EQ(parts.back().highestFrequency(), 4.0f * std::exp2(static_cast<float>(o)));
    EXPECT_NE(parts.back().fingerprint(), all.fingerprint());
  }
  FractalNoiseOptions first = whole;
  first.octaves = 1;
  EXPECT_NE(parts[0].fingerprint(), parts[1].fingerprint());
  Rng rng(3);
  double worstH = 0.0, worstG = 0.0;
  for (int i = 0; i < 2000; ++i) {
    const Vec2 p(rng.uniform(), rng.uniform());
    float h = 0.0f;
    Vec2 g(0.0f);
    for (const FractalNoise& n : parts) h += n.height(p), g += n.gradient(p);
    worstH = std::max(worstH, static_cast<double>(std::abs(h - all.height(p))));
    worstG = std::max(worstG, static_cast<double>(glm::length(g - all.gradient(p))));
  }
  EXPECT_LT(worstH, 1e-6);
  EXPECT_LT(worstG, 1e-4);  // gradients grow with frequency: up to 4 * 2^4 * 2 pi
  // Octave 0 alone is the one-octave noise of the same seed.
  EXPECT_FLOAT_EQ(parts[0].height(Vec2(0.3f, 0.7f)), FractalNoise(first).height(Vec2(0.3f, 0.7f)));
  FractalNoiseOptions bad = whole;
  bad.firstOctave = 5;
  EXPECT_THROW(FractalNoise{bad}, Error);
}

}  // namespace
}  // namespace meso
