#include "meso/appearance/class_derivation.h"

#include "meso/appearance/histogram_builder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace meso {
namespace {

// Two crossed waves and an oblique one: no symmetry that a wrong map could hide behind.
struct WavyRelief : PeriodicRelief {
  float s;
  explicit WavyRelief(float scale) : s(scale) {}
  float height(float x, float y) const override {
    return s * (0.06f * std::sin(2 * kPi * x) * std::sin(2 * kPi * y) +
                0.03f * std::sin(2 * kPi * (2 * x + y) + 0.3f));
  }
  Vec2 gradient(float x, float y) const override {
    const float w = 2 * kPi, c = std::cos(w * (2 * x + y) + 0.3f);
    return {s * (0.06f * w * std::cos(w * x) * std::sin(w * y) + 0.03f * w * 2 * c),
            s * (0.06f * w * std::sin(w * x) * std::cos(w * y) + 0.03f * w * c)};
  }
  uint64_t fingerprint() const override { return static_cast<uint64_t>(s * 1e6f); }
};

HistogramSettings settings(MetricShape shape, uint64_t seed) {
  HistogramSettings h;
  h.resolution = {8, 48, 16, 8};
  h.azimuths = 16;
  h.raysPerView = 4000;
  h.meshResolution = 96;
  h.seed = seed;
  h.shape = shape;
  return h;
}

// Per view slice: the mean visible normal and its second moments in the view-aligned frame.
struct Moments {
  Vec3 mean{0.0f};
  float xx = 0.0f, yy = 0.0f, xy = 0.0f;
};

Moments momentsOf(const VisibleNormalHistogram& h, int k) {
  Moments m;
  const HistogramResolution& r = h.resolution();
  for (int i = 0; i < r.thetaN; ++i)
    for (int j = 0; j < r.phi; ++j) {
      const float w = h.mass(k, i, j);
      const Vec3 n = h.binDirection(i, j);
      m.mean += w * n;
      m.xx += w * n.x * n.x, m.yy += w * n.y * n.y, m.xy += w * n.x * n.y;
    }
  return m;
}

// The largest difference of mean normal and second moments over the slices up to theta_V 70
// degrees (beyond, the tile's slices are far apart for the view's interpolation).
float worstDifference(const VisibleNormalHistogram& a, const VisibleNormalHistogram& b) {
  float worst = 0.0f;
  for (int k = 0; k < a.numSlices(); ++k) {
    if (a.sliceThetaV(k) > 1.23f) continue;
    const Moments x = momentsOf(a, k), y = momentsOf(b, k);
    worst = std::max({worst, glm::length(x.mean - y.mean), std::abs(x.xx - y.xx),
                      std::abs(x.yy - y.yy), std::abs(x.xy - y.xy)});
  }
  return worst;
}

// A stretched and sheared class whose heights are 1.3 times the tile's: its traced histogram
// against the one derived from the isotropic tile (traced with twice the view-azimuth slices, as
// the tables do) through M^-1 (views) and M^-T (normals). Two traced histograms of different seeds
// set the noise floor. Wrong maps must fail the bound: M in place of M^-T on the diagonal (1 / a,
// 1 / t), the shear's sign, the inverse height scale alone.
TEST(ClassDerivation, DerivedHistogramOfAStretchedShearedClassMatchesTheTracedOne) {
  const MetricShape shape{1.4f, 0.5f};
  const float t = 1.3f;
  HistogramSettings tileSettings = settings({}, 1);
  tileSettings.resolution.phiV *= 2;
  tileSettings.azimuths *= 2;
  const VisibleNormalHistogram tile = buildVisibleNormalHistogram(WavyRelief(1.0f), tileSettings);
  const VisibleNormalHistogram traced =
      buildVisibleNormalHistogram(WavyRelief(t), settings(shape, 2));
  const VisibleNormalHistogram again =
      buildVisibleNormalHistogram(WavyRelief(t), settings(shape, 3));
  const HistogramSettings s = settings(shape, 1);
  const auto derived = [&](const ClassMap& m) {
    return deriveHistogram(tile, m, s.resolution, s.azimuths);
  };
  const float noise = worstDifference(traced, again);
  const float right = worstDifference(derived({shape, t}), traced);
  const float transposed = worstDifference(derived({{1.0f / shape.a, shape.b}, 1.0f / t}), traced);
  const float wrongShear = worstDifference(derived({{shape.a, -shape.b}, t}), traced);
  const float wrongHeight = worstDifference(derived({shape, 1.0f / t}), traced);
  std::printf(
      "noise %.4f, derived %.4f; wrong maps: M on the diagonal %.4f, shear %.4f, height "
      "%.4f\n",
      noise, right, transposed, wrongShear, wrongHeight);
  const float bound = 0.03f;
  EXPECT_LT(noise, bound);
  EXPECT_LT(right, bound);
  EXPECT_GT(transposed, 2.0f * bound);
  EXPECT_GT(wrongShear, 2.0f * bound);
  EXPECT_GT(wrongHeight, 2.0f * bound);
}

}  // namespace
}  // namespace meso
