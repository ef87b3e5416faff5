#include "meso/appearance/brdf_table.h"

#include "meso/core/math.h"
#include "meso/core/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

namespace meso {
namespace {

VisibleNormalHistogram flatHistogram() {
  VisibleNormalHistogram h(HistogramResolution{6, 16, 16});
  for (int k = 0; k < 6; ++k) h.add(k, Vec3(0.0f, 0.0f, 1.0f), 100.0f);
  h.normalize();
  return h;
}

// A rough histogram from random unit normals up to 34 degrees from the macro normal; as for real
// visible normals, none faces away from the viewer.
VisibleNormalHistogram roughHistogram() {
  VisibleNormalHistogram h(HistogramResolution{6, 16, 16});
  Rng rng(17);
  for (int k = 0; k < 6; ++k) {
    const Vec3 V(std::sin(h.thetaV(k)), 0.0f, std::cos(h.thetaV(k)));
    for (int n = 0; n < 20000; ++n) {
      const float t = 0.6f * rng.uniform(), p = 2.0f * kPi * rng.uniform();
      const Vec3 N(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
      if (glm::dot(N, V) > 0.05f) h.add(k, N);
    }
  }
  h.normalize();
  return h;
}

TEST(BrdfTable, ZeroReliefDiffuseIsExactlyLDotN) {
  const BrdfTable t = BrdfTable::fromDistribution(flatHistogram(), {9, 7}, 30.0f);
  for (int k = 0; k < t.numThetaV(); ++k)
    for (int i = 0; i < 9; ++i)
      for (int j = 0; j < 7; ++j) {
        EXPECT_FLOAT_EQ(t.entry(k, i, j).diffuse, std::max(std::cos(t.thetaL(i)), 0.0f));
        const Vec3 V(std::sin(t.thetaV(k)), 0.0f, std::cos(t.thetaV(k)));
        const Vec3 L(std::sin(t.thetaL(i)) * std::cos(-t.phi(j)),
                     std::sin(t.thetaL(i)) * std::sin(-t.phi(j)), std::cos(t.thetaL(i)));
        const Vec3 H = glm::normalize(V + L);
        // Lit facets only, as the local model (theta_L = 90 degrees lights nothing).
        EXPECT_NEAR(t.entry(k, i, j).specular, L.z > 0.0f ? std::pow(H.z, 30.0f) : 0.0f, 1e-5f);
      }
}

// Past theta_L = 90 degrees: every visible normal tilted 30 degrees towards the viewer's side
// (azimuth 0) gives diffuse = max(0, N.L) exactly, which stays positive for lights below the mean
// plane up to 120 degrees on that side; the flat relief gives 0 there. The axis goes on to pi at
// the spacing of the res.thetaL nodes over [0, pi / 2].
TEST(BrdfTable, LightsBelowTheMeanPlaneLightTheFacetsThatFaceThem) {
  const Vec3 N(std::sin(0.5236f), 0.0f, std::cos(0.5236f));
  VisibleNormalHistogram h(HistogramResolution{6, 16, 16});
  for (int k = 0; k < 6; ++k) h.add(k, N, 100.0f);
  h.normalize();
  const BrdfTable tilted = BrdfTable::fromDistribution(h, {9, 7}, 30.0f);
  const BrdfTable flat = BrdfTable::fromDistribution(flatHistogram(), {9, 7}, 30.0f);
  ASSERT_EQ(BrdfTable::thetaLNodes({9, 7}), 17);
  EXPECT_FLOAT_EQ(tilted.thetaL(8), 0.5f * kPi);
  EXPECT_FLOAT_EQ(tilted.thetaL(16), kPi);
  int lit = 0;
  for (int k = 0; k < tilted.numThetaV(); ++k)
    for (int i = 9; i < 17; ++i)
      for (int j = 0; j < 7; ++j) {
        const Vec3 L(std::sin(tilted.thetaL(i)) * std::cos(-tilted.phi(j)),
                     std::sin(tilted.thetaL(i)) * std::sin(-tilted.phi(j)),
                     std::cos(tilted.thetaL(i)));
        EXPECT_NEAR(tilted.entry(k, i, j).diffuse, std::max(glm::dot(N, L), 0.0f), 1e-5f);
        EXPECT_EQ(flat.entry(k, i, j).diffuse, 0.0f);
        lit += tilted.entry(k, i, j).diffuse > 0.0f;
      }
  EXPECT_GT(lit, 0);
  // Looked up between the nodes too: 100 degrees, phi_{V-L} = 0.
  const float t = 100.0f * kPi / 180.0f;
  EXPECT_NEAR(tilted.lookup(tilted.thetaV(0), t, 0.0f).diffuse, std::cos(t - 0.5236f), 0.01f);
}

TEST(BrdfTable, EntriesFiniteAndNonNegativeIncludingGrazing) {
  const VisibleNormalHistogram h = roughHistogram();
  const BrdfTable fine = BrdfTable::fromDistribution(h, {9, 7}, 50.0f);
  const BrdfTable coarse = BrdfTable::fromFinerLevel(h, {9, 7}, fine);
  for (const BrdfTable* t : {&fine, &coarse}) {
    for (float v : t->data()) {
      ASSERT_TRUE(std::isfinite(v));
      ASSERT_GE(v, 0.0f);
    }
    for (float tv : {0.0f, 1.0f, kPi / 2, 2.0f})
      for (float tl : {0.0f, kPi / 2, 1.7f})
        for (float p : {0.0f, kPi, -1.0f, 7.0f, NAN}) {
          const BrdfTable::Value v = t->lookup(tv, tl, p);
          ASSERT_TRUE(std::isfinite(v.diffuse) && std::isfinite(v.specular));
          ASSERT_GE(v.diffuse, 0.0f);
        }
  }
  // With L at the zenith the diffuse term is the mean cos(theta_N): below 1 for a rough relief.
  EXPECT_LT(fine.entry(0, 0, 0).diffuse, 0.99f);
  EXPECT_GT(fine.entry(0, 0, 0).diffuse, 0.8f);
}

// Trilinear lookups reproduce the nodes and interpolate linearly between them.
TEST(BrdfTable, LookupInterpolatesTrilinearly) {
  const BrdfTable t = BrdfTable::fromDistribution(roughHistogram(), {9, 7}, 10.0f);
  EXPECT_FLOAT_EQ(t.lookup(t.thetaV(2), t.thetaL(3), t.phi(4)).diffuse, t.entry(2, 3, 4).diffuse);
  const float mid = 0.5f * (t.thetaL(3) + t.thetaL(4));
  EXPECT_NEAR(t.lookup(t.thetaV(2), mid, t.phi(4)).diffuse,
              0.5f * (t.entry(2, 3, 4).diffuse + t.entry(2, 4, 4).diffuse), 1e-6f);
  // phi is |phi_V - phi_L| modulo 2 pi.
  EXPECT_FLOAT_EQ(t.lookup(0.3f, 0.4f, -0.5f).diffuse, t.lookup(0.3f, 0.4f, 0.5f).diffuse);
  EXPECT_NEAR(t.lookup(0.3f, 0.4f, 2.0f * kPi - 0.5f).diffuse, t.lookup(0.3f, 0.4f, 0.5f).diffuse,
              1e-5f);
}

// A flat finer level makes the coarser table equal to the finest table of the coarse relief.
TEST(BrdfTable, RecursionOverAFlatFinerLevelIsTheOneLevelTable) {
  const VisibleNormalHistogram rough = roughHistogram();
  const BrdfTable flatFine = BrdfTable::fromDistribution(flatHistogram(), {17, 13}, 1.0f);
  const BrdfTable twoLevel = BrdfTable::fromFinerLevel(rough, {9, 7}, flatFine);
  const BrdfTable oneLevel = BrdfTable::fromDistribution(rough, {9, 7}, 1.0f);
  double maxErr = 0.0;
  for (int k = 0; k < oneLevel.numThetaV(); ++k)
    for (int i = 0; i < 8; ++i)  // below grazing light
      for (int j = 0; j < 7; ++j)
        maxErr = std::max(maxErr, std::abs(static_cast<double>(twoLevel.entry(k, i, j).diffuse) -
                                           oneLevel.entry(k, i, j).diffuse));
  EXPECT_LT(maxErr, 1e-3);  // measured 2.8e-4: normalizing bin means and trilinear error
}

}  // namespace
}  // namespace meso

namespace meso {
namespace {

// A specular lobe given as a function is the same table as the built-in (H.N)^phong when it is
// that function, and a wider lobe gives a wider highlight (more specular away from the mirror).
TEST(BrdfTable, SpecularLobeGeneralizesPhong) {
  const VisibleNormalHistogram h = roughHistogram();
  const BrdfResolution res{8, 8};
  const BrdfTable phong = BrdfTable::fromDistribution(h, res, 30.0f);
  const SpecularLobe same{[](float c) { return std::pow(std::max(c, 0.0f), 30.0f); }, 1};
  // The built-in exponent is raised by repeated squaring, the lobe by std::pow: equal to a few
  // float roundings.
  const std::vector<float> general = BrdfTable::fromDistribution(h, res, same).data();
  ASSERT_EQ(general.size(), phong.data().size());
  for (size_t e = 0; e < general.size(); ++e)
    EXPECT_NEAR(general[e], phong.data()[e], 1e-5f * std::max(1.0f, phong.data()[e]));
  const SpecularLobe wide{[](float c) { return std::pow(std::max(c, 0.0f), 5.0f); }, 2};
  const BrdfTable w = BrdfTable::fromDistribution(h, res, wide);
  EXPECT_GT(w.lookup(0.2f, 1.2f, 0.0f).specular, phong.lookup(0.2f, 1.2f, 0.0f).specular);
  const SpecularLobe broken{[](float) { return std::nanf(""); }, 3};
  const BrdfTable b = BrdfTable::fromDistribution(h, res, broken);
  for (float v : b.data()) EXPECT_TRUE(std::isfinite(v));
}

}  // namespace
}  // namespace meso

namespace meso {
namespace {

// A rough histogram at the renderer's resolution (96 x 32 bins, 4 view slices).
VisibleNormalHistogram fineRoughHistogram() {
  VisibleNormalHistogram h(HistogramResolution{4, 96, 32});
  Rng rng(5);
  for (int k = 0; k < 4; ++k) {
    const Vec3 V(std::sin(h.thetaV(k)), 0.0f, std::cos(h.thetaV(k)));
    for (int n = 0; n < 200000; ++n) {
      const float t = 0.5f * std::sqrt(-std::log(std::max(rng.uniform(), 1e-7f)));
      const float p = 2.0f * kPi * rng.uniform();
      const Vec3 N(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
      if (t < 1.5f && glm::dot(N, V) > 0.0f) h.add(k, N, glm::dot(N, V) / N.z);
    }
  }
  h.normalize();
  return h;
}

// Grouping bins into quadrature normals (the default widths) against every bin its own point: the
// diffuse term, linear in N, is exact wherever every normal is lit (the light at the zenith), and
// the Phong and finer-level terms stay within a small fraction of their values. A grouping four
// times as wide is measurably worse, so the comparison can fail.
TEST(BrdfTable, GroupedQuadratureNormalsMatchEveryBin) {
  const VisibleNormalHistogram h = fineRoughHistogram();
  BrdfResolution every{9, 7};
  every.finest = every.coarser = NormalGrouping{};
  const BrdfResolution grouped{9, 7};
  BrdfResolution wide = grouped;
  wide.finest = {4.0f * grouped.finest.thetaN, 4.0f * grouped.finest.phi};
  wide.coarser = {4.0f * grouped.coarser.thetaN, 4.0f * grouped.coarser.phi};
  const BrdfTable exact = BrdfTable::fromDistribution(h, every, 40.0f);
  const BrdfTable fast = BrdfTable::fromDistribution(h, grouped, 40.0f);
  const BrdfTable coarse = BrdfTable::fromDistribution(h, wide, 40.0f);
  for (int k = 0; k < exact.numThetaV(); ++k)
    EXPECT_NEAR(fast.entry(k, 0, 0).diffuse, exact.entry(k, 0, 0).diffuse, 1e-5f);
  // Relative error of the specular sums over the whole table (mean and worst node above 1% of
  // the table's peak).
  const auto specularError = [&](const BrdfTable& t, const BrdfTable& ref, double* worst) {
    double num = 0.0, den = 0.0, peak = 0.0;
    for (float v : ref.data()) peak = std::max(peak, static_cast<double>(v));
    *worst = 0.0;
    const size_t half = ref.data().size() / 2;
    for (size_t e = half; e < ref.data().size(); ++e) {
      const double d = std::abs(t.data()[e] - ref.data()[e]);
      num += d, den += ref.data()[e];
      if (ref.data()[e] > 0.01 * peak) *worst = std::max(*worst, d / ref.data()[e]);
    }
    return num / den;
  };
  double worstFast = 0.0, worstCoarse = 0.0;
  const double meanFast = specularError(fast, exact, &worstFast);
  const double meanCoarse = specularError(coarse, exact, &worstCoarse);
  // Measured: mean 0.05%, worst node 1.6% (a highlight's tail); four times as wide 8.6% and 68%.
  EXPECT_LT(meanFast, 0.002);
  EXPECT_LT(worstFast, 0.03);
  EXPECT_GT(meanCoarse, 10.0 * meanFast);
  // Eq. (1) over a finer level: the same relief's table as the finer level.
  const BrdfTable exactTwo = BrdfTable::fromFinerLevel(h, every, exact);
  const BrdfTable fastTwo = BrdfTable::fromFinerLevel(h, grouped, exact);
  double num = 0.0, den = 0.0;
  for (size_t e = 0; e < exactTwo.data().size(); ++e)
    num += std::abs(fastTwo.data()[e] - exactTwo.data()[e]), den += exactTwo.data()[e];
  EXPECT_LT(num / den, 0.002);
}

}  // namespace
}  // namespace meso

namespace meso {
namespace {

// The integration leaves out the blocks of quadrature normals that a light cannot reach (every
// one facing away from it). Every node of a broad histogram's table, lights below the mean plane
// included, is still the sum over every bin: nothing lit was left out.
TEST(BrdfTable, BlocksLeftOutHoldNoLitNormal) {
  const VisibleNormalHistogram h = fineRoughHistogram();
  BrdfResolution every{9, 7};
  every.finest = NormalGrouping{};
  const float phong = 20.0f;
  const BrdfTable t = BrdfTable::fromDistribution(h, every, phong);
  const HistogramResolution& r = h.resolution();
  size_t below = 0;
  for (int k = 0; k < t.numThetaV(); ++k) {
    const Vec3 V = polarDirection(h.sliceThetaV(k), 0.0f);
    for (int i = 0; i < BrdfTable::thetaLNodes(every); ++i)
      for (int j = 0; j < BrdfTable::phiNodes(every, 1); ++j) {
        const Vec3 L = polarDirection(t.thetaL(i), -t.phi(j));
        const Vec3 H = glm::normalize(V + L);
        double diffuse = 0.0, specular = 0.0;
        for (int a = 0; a < r.thetaN; ++a)
          for (int b = 0; b < r.phi; ++b) {
            const double m = h.mass(k, a, b);
            if (m == 0.0) continue;
            const Vec3 n = h.meanNormal(k, a, b);
            const double lDotN = glm::dot(L, n);
            if (lDotN <= 0.0) continue;
            diffuse += m * lDotN;
            specular += m * std::pow(std::clamp(glm::dot(H, glm::normalize(n)), 0.0f, 1.0f), phong);
          }
        const BrdfTable::Value v = t.entry(k, i, j);
        EXPECT_NEAR(v.diffuse, diffuse, 1e-5 * std::max(1.0, diffuse)) << k << " " << i << " " << j;
        EXPECT_NEAR(v.specular, specular, 1e-5 * std::max(1.0, specular))
            << k << " " << i << " " << j;
        if (t.thetaL(i) > 0.5f * kPi && diffuse > 1e-3) ++below;
      }
  }
  EXPECT_GT(below, 100u);  // the lights where blocks are left out light some facets
}

}  // namespace
}  // namespace meso

namespace meso {
namespace {

// The finest level's Phong integration runs in AVX2 where the CPU has it and in the baseline x86-64
// vectors elsewhere: the same float operations in the same order, so the same tables to the bit
// (a fused multiply-add or a reordered sum in either would break this), with whole and fractional
// exponents, on isotropic and view-azimuth tables.
TEST(BrdfTable, WideAndBaselineVectorsGiveTheSameBits) {
  if (!brdfHasWiderVectors()) GTEST_SKIP() << "this CPU has no wider vectors than the baseline";
  VisibleNormalHistogram aniso(HistogramResolution{3, 96, 32, 4});
  Rng rng(23);
  for (int k = 0; k < aniso.numSlices(); ++k)
    for (int n = 0; n < 50000; ++n) {
      const float t = 0.7f * rng.uniform(), p = 2.0f * kPi * rng.uniform();
      const Vec3 N(1.6f * std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
      aniso.add(k, glm::normalize(N));
    }
  aniso.normalize();
  const VisibleNormalHistogram iso = fineRoughHistogram();
  const BrdfResolution res{9, 7};
  for (const VisibleNormalHistogram* h : {&iso, static_cast<const VisibleNormalHistogram*>(&aniso)})
    for (float phong : {1.0f, 20.0f, 37.5f, 300.0f}) {
      setBrdfVectors(BrdfVectors::baseline);
      const BrdfTable base = BrdfTable::fromDistribution(*h, res, phong);
      setBrdfVectors(BrdfVectors::best);
      const BrdfTable wide = BrdfTable::fromDistribution(*h, res, phong);
      ASSERT_EQ(base.data().size(), wide.data().size());
      size_t differ = 0, lit = 0;
      for (size_t e = 0; e < base.data().size(); ++e) {
        differ += std::memcmp(&base.data()[e], &wide.data()[e], sizeof(float)) != 0;
        lit += base.data()[e] > 0.0f;
      }
      EXPECT_EQ(differ, 0u) << "phong " << phong;
      EXPECT_GT(lit, base.data().size() / 4) << "phong " << phong;
    }
}

}  // namespace
}  // namespace meso
