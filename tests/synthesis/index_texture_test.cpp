// Kautz et al. 2001, section 7: a relief's normals converted to indices into L come back when L is
// sampled at the index (within one table cell), for an estimated Beckmann and a tabulated NDF;
// noise added with an amplitude moves them away smoothly.
#include "meso/relief/fractal_noise.h"
#include "meso/synthesis/beckmann_ndf.h"
#include "meso/synthesis/index_texture.h"
#include "meso/synthesis/ndf_estimate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace meso {
namespace {

float angleBetween(const Vec3& a, const Vec3& b) {
  return 2.0f * std::asin(std::min(1.0f, 0.5f * glm::length(a - b)));
}

struct RoundTrip {
  float maxError = 0.0f;      // radians, over texels the table can reach
  float maxCellAngle = 0.0f;  // the largest table cell met
  int outside = 0;            // texels whose normal lies beyond the NDF's support box
  int violations = 0;         // texels with error > their table cell's angle
};

RoundTrip roundTrip(const IndexTexture& tex, const NormalLookupTable& table) {
  RoundTrip r;
  const Vec2 s = table.support();
  for (int j = 0; j < tex.resolution(); ++j)
    for (int i = 0; i < tex.resolution(); ++i) {
      const Vec3 n = tex.originalNormal(i, j);
      if (std::abs(n.x) > s.x || std::abs(n.y) > s.y) {
        ++r.outside;
        continue;
      }
      const Vec2 index = tex.index(i, j);
      const float error = angleBetween(table.lookup(index), n), cell = table.cellAngle(index);
      r.maxError = std::max(r.maxError, error);
      r.maxCellAngle = std::max(r.maxCellAngle, cell);
      r.violations += error > cell + 1e-5f;
    }
  return r;
}

const FractalNoise& relief() {
  static const FractalNoise noise(FractalNoiseOptions{5, 2.0f, 0.5f, 77, 4.0f, true});
  return noise;
}
constexpr float kSlopeScale = 0.06f;  // rms slope about 0.35 (Beckmann alpha about 0.48)

TEST(IndexTexture, RoundTripWithEstimatedBeckmann) {
  NdfEstimateOptions o;
  o.slopeScale = kSlopeScale;
  const NdfEstimate e = estimateNdf(relief(), o);
  // The table is in the NDF's principal frame: rotate the relief into it.
  struct Rotated : HeightSource {
    const HeightSource* s;
    float c, sn;
    float height(Vec2 p) const override { return s->height(p); }
    Vec2 gradient(Vec2 p) const override {
      const Vec2 g = s->gradient(p);
      return Vec2(c * g.x + sn * g.y, -sn * g.x + c * g.y);
    }
    float highestFrequency() const override { return s->highestFrequency(); }
    uint64_t fingerprint() const override { return 0; }
  } rotated;
  rotated.s = &relief(), rotated.c = std::cos(e.principalAngle),
  rotated.sn = std::sin(e.principalAngle);
  const NormalLookupTable table(*e.ndf);
  const IndexTexture tex(rotated, table, 128, kSlopeScale);
  const RoundTrip r = roundTrip(tex, table);
  std::printf(
      "[index] %s: max error %.4f deg, largest cell %.3f deg, %d of %d beyond the support box\n",
      e.ndf->name().c_str(), degrees(r.maxError), degrees(r.maxCellAngle), r.outside, 128 * 128);
  EXPECT_EQ(r.violations, 0);
  EXPECT_LT(r.outside, 128 * 128 / 100);
  EXPECT_LT(degrees(r.maxError), 0.01f);  // invert() is the exact inverse of the bilinear table
}

TEST(IndexTexture, RoundTripWithTabulatedNdfAndNoise) {
  NdfEstimateOptions o;
  o.slopeScale = kSlopeScale;
  o.model = NdfModel::Tabulated;
  o.samples = 512;
  const NdfEstimate e = estimateNdf(relief(), o);
  const SynthesisSampler sampler(*e.ndf);
  const IndexTexture tex(relief(), sampler.table(), 128, kSlopeScale);
  const RoundTrip r = roundTrip(tex, sampler.table());
  std::printf("[index] %s: max error %.4f deg, largest cell %.3f deg, %d beyond the support box\n",
              e.ndf->name().c_str(), degrees(r.maxError), degrees(r.maxCellAngle), r.outside);
  EXPECT_EQ(r.violations, 0);
  EXPECT_EQ(r.outside, 0);
  EXPECT_LT(degrees(r.maxError), 0.01f);

  // At texel centres, amplitude 0 gives the relief's normal; more amplitude moves further from it.
  float previous = -1.0f;
  for (float amplitude : {0.0f, 0.1f, 0.4f, 1.5f}) {
    double sum = 0.0;
    for (int j = 0; j < 64; ++j)
      for (int i = 0; i < 64; ++i) {
        const Vec2 p((2 * i + 0.5f) / 128.0f, (2 * j + 0.5f) / 128.0f);
        const Vec3 n = tex.normal(sampler, p, amplitude, 4.0f);
        ASSERT_TRUE(isFinite(n));
        ASSERT_NEAR(glm::length(n), 1.0f, 1e-4f);
        sum += angleBetween(n, tex.originalNormal(2 * i, 2 * j));
      }
    const float mean = degrees(static_cast<float>(sum / (64 * 64)));
    std::printf("[index] noise amplitude %.1f: mean deviation %.3f deg\n", amplitude, mean);
    if (amplitude == 0.0f) {
      EXPECT_LT(mean, 0.01f);
    }
    EXPECT_GT(mean, previous);
    previous = mean;
  }
}

TEST(IndexTexture, BilinearIndexIsPeriodic) {
  const BeckmannNdf ndf(0.3f);
  const NormalLookupTable table(ndf);
  const IndexTexture tex(relief(), table, 32, kSlopeScale);
  for (Vec2 p : {Vec2(0.01f, 0.5f), Vec2(0.99f, 0.02f), Vec2(0.3f, 0.7f)}) {
    const Vec2 a = tex.index(p), b = tex.index(p + Vec2(1.0f, -2.0f));
    EXPECT_NEAR(a.x, b.x, 1e-4f);
    EXPECT_NEAR(a.y, b.y, 1e-4f);
  }
  const Vec2 c = tex.index(Vec2(std::nanf(""), 0.0f));
  EXPECT_TRUE(std::isfinite(c.x) && std::isfinite(c.y));
}

}  // namespace
}  // namespace meso
