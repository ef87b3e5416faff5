// Kautz et al. 2001, section 7: NDFs estimated from a relief's slopes.
#include "meso/core/error.h"
#include "meso/relief/fractal_noise.h"
#include "meso/synthesis/beckmann_ndf.h"
#include "meso/synthesis/ndf_estimate.h"
#include "meso/synthesis/tabulated_ndf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace meso {
namespace {

// h = A sin(2 pi (x cos a + y sin a)) + B sin(2 pi (-x sin a + y cos a)): slope variances
// (2 pi A)^2 / 2 and (2 pi B)^2 / 2 along the axes rotated by a, so Beckmann alphas 2 pi A, 2 pi B.
struct Corrugations : HeightSource {
  float A, B, a;
  Corrugations(float A_, float B_, float a_) : A(A_), B(B_), a(a_) {}
  // Integer wave vectors keep the tile periodic; angles with small integer directions only.
  float height(Vec2) const override { return 0.0f; }
  Vec2 gradient(Vec2 p) const override {
    const float tau = 2.0f * std::numbers::pi_v<float>, c = std::cos(a), s = std::sin(a);
    const Vec2 k1 = Vec2(c, s), k2 = Vec2(-s, c);
    // Frequencies 3 and 5 per tile along the rotated axes (irrational for most angles; fine on
    // the 256^2 sample grid).
    return tau * A * 3.0f * std::cos(tau * 3.0f * glm::dot(k1, p)) * k1 +
           tau * B * 5.0f * std::cos(tau * 5.0f * glm::dot(k2, p)) * k2;
  }
  float highestFrequency() const override { return 5.0f; }
  uint64_t fingerprint() const override { return 1; }
};

TEST(NdfEstimate, BeckmannFromSlopeCovarianceAndPrincipalFrame) {
  for (float angle : {0.0f, 0.5f, -1.0f}) {
    const Corrugations relief(0.02f, 0.004f, angle);
    NdfEstimateOptions o;
    o.samples = 512;
    const NdfEstimate e = estimateNdf(relief, o);
    const auto* beckmann = dynamic_cast<const BeckmannNdf*>(e.ndf.get());
    ASSERT_NE(beckmann, nullptr);
    const float tau = 2.0f * std::numbers::pi_v<float>;
    EXPECT_NEAR(beckmann->alphaX(), tau * 0.02f * 3.0f, 0.03f * tau * 0.02f * 3.0f) << angle;
    EXPECT_NEAR(beckmann->alphaY(), tau * 0.004f * 5.0f, 0.03f * tau * 0.004f * 5.0f) << angle;
    EXPECT_NEAR(e.principalAngle, angle, 0.02f);
  }
}

TEST(NdfEstimate, FlatReliefGivesTheSharpestBeckmannAndAOneCellTable) {
  const Corrugations flat(0.0f, 0.0f, 0.0f);
  const NdfEstimate e = estimateNdf(flat);
  const auto* beckmann = dynamic_cast<const BeckmannNdf*>(e.ndf.get());
  ASSERT_NE(beckmann, nullptr);
  EXPECT_FLOAT_EQ(beckmann->alphaX(), 1e-4f);
  EXPECT_TRUE(std::isfinite(e.ndf->D(Vec3(0, 0, 1))));
  NdfEstimateOptions o;
  o.model = NdfModel::Tabulated;
  const NdfEstimate t = estimateNdf(flat, o);
  EXPECT_GT(t.ndf->D(Vec3(0, 0, 1)), 0.0f);
  EXPECT_THROW(estimateNdf(flat, NdfEstimateOptions{.samples = 1}), Error);
}

TEST(NdfEstimate, TabulatedMatchesTheReliefsNormalMoments) {
  const FractalNoise relief(FractalNoiseOptions{4, 2.0f, 0.5f, 3, 4.0f, true});
  NdfEstimateOptions o;
  o.model = NdfModel::Tabulated;
  o.samples = 512;
  o.slopeScale = 0.08f;
  const NdfEstimate e = estimateNdf(relief, o);
  // E[m.x^2] over the relief versus over the NDF (disk density D).
  double relX = 0.0, relY = 0.0;
  const int n = 512;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const Vec2 s = 0.08f * relief.gradient(Vec2((i + 0.5f) / n, (j + 0.5f) / n));
      const Vec3 m = glm::normalize(Vec3(-s.x, -s.y, 1.0f));
      relX += m.x * m.x, relY += m.y * m.y;
    }
  relX /= n * n, relY /= n * n;
  double ndfX = 0.0, ndfY = 0.0, mass = 0.0;
  const int g = 600;
  for (int j = 0; j < g; ++j)
    for (int i = 0; i < g; ++i) {
      const double x = -1.0 + (i + 0.5) * 2.0 / g, y = -1.0 + (j + 0.5) * 2.0 / g,
                   r2 = x * x + y * y;
      if (r2 >= 1.0) continue;
      const double d = e.ndf->D(Vec3(static_cast<float>(x), static_cast<float>(y),
                                     static_cast<float>(std::sqrt(1.0 - r2))));
      ndfX += d * x * x, ndfY += d * y * y, mass += d;
    }
  const double cell = 4.0 / (g * g);
  EXPECT_NEAR(mass * cell, 1.0, 2e-3);
  // The histogram's cells (2/64 wide) and their bilinear spread add about cell^2 / 12 + ... each.
  EXPECT_NEAR(ndfX * cell, relX, 0.06 * relX + 2e-4);
  EXPECT_NEAR(ndfY * cell, relY, 0.06 * relY + 2e-4);
}

TEST(NdfEstimate, NdfTangentRotatesAboutTheNormal) {
  const Vec3 N(0, 0, 1), T(1, 0, 0.3f);
  const Vec3 t = ndfTangent(N, T, std::numbers::pi_v<float> / 2);
  EXPECT_NEAR(t.x, 0.0f, 1e-6f);
  EXPECT_NEAR(t.y, 1.0f, 1e-6f);
  EXPECT_NEAR(t.z, 0.0f, 1e-6f);
}

}  // namespace
}  // namespace meso
