// Kautz et al. 2001, section 5.1: the half vector in the synthesized microfacet's frame indexes D.
#include "meso/core/rng.h"
#include "meso/synthesis/beckmann_ndf.h"
#include "meso/synthesis/synthesized_shading.h"

#include <gtest/gtest.h>

#include <cmath>

namespace meso {
namespace {

Vec3 dir(float theta, float phi) {
  return Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

TEST(SynthesizedShading, FlatMicrofacetIsPlainNdfShading) {
  const BeckmannNdf ndf(0.2f, 0.5f);
  const Vec3 N(0, 0, 1), T(1, 0, 0), V = dir(0.4f, 0.3f), L = dir(0.7f, 2.5f);
  const SynthesizedShading s = shadeSynthesized(ndf, N, T, V, L, Vec3(0, 0, 1));
  EXPECT_NEAR(s.specular, ndf.D(glm::normalize(V + L)), 1e-4f * s.specular);
  EXPECT_NEAR(s.diffuse, L.z, 1e-6f);
}

TEST(SynthesizedShading, MicrofacetFrameIsARotationTakingZToM) {
  Rng rng(7, 1);
  for (int k = 0; k < 200; ++k) {
    const Vec3 m = dir(1.5f * rng.uniform(), 6.28f * rng.uniform());
    const Vec3 z = toMicrofacetFrame(m, m);
    EXPECT_NEAR(z.z, 1.0f, 1e-5f);
    const Vec3 h = dir(1.5f * rng.uniform(), 6.28f * rng.uniform()), hm = toMicrofacetFrame(m, h);
    EXPECT_NEAR(glm::length(hm), 1.0f, 1e-5f);
    EXPECT_NEAR(hm.z, glm::dot(h, m), 1e-6f);
  }
  // m = z: the identity.
  const Vec3 h = dir(0.5f, 1.0f), same = toMicrofacetFrame(Vec3(0, 0, 1), h);
  EXPECT_NEAR(glm::length(same - h), 0.0f, 1e-6f);
}

TEST(SynthesizedShading, TiltedMicrofacetAndTangentFrame) {
  // A world frame with N along +y and T along +z: m tilted towards T.
  const BeckmannNdf ndf(0.3f, 0.1f);
  const Vec3 N(0, 1, 0), T(0, 0, 1);
  const Vec3 m = glm::normalize(Vec3(0.3f, 0.0f, 1.0f));  // NDF frame: tilted along the principal x
  const Vec3 mWorld = ndfFrameToWorld(N, T, m);
  EXPECT_NEAR(glm::length(mWorld - glm::normalize(Vec3(0.0f, 1.0f, 0.3f))), 0.0f, 1e-6f);
  // Mirror V about the tilted facet: the half vector is the facet normal, h_m = z, D maximal.
  const Vec3 V = glm::normalize(Vec3(0.2f, 1.0f, -0.1f)),
             L = 2.0f * glm::dot(V, mWorld) * mWorld - V;
  const SynthesizedShading s = shadeSynthesized(ndf, N, T, V, L, m);
  EXPECT_NEAR(s.specular, ndf.D(Vec3(0, 0, 1)), 1e-3f * s.specular);
  EXPECT_NEAR(s.diffuse, glm::dot(L, mWorld), 1e-5f);
  // Swapping the tangent by 90 degrees and the alphas gives the same result (the frame is used).
  const BeckmannNdf swapped(0.1f, 0.3f);
  const Vec3 T2 = glm::cross(N, T);  // the old bitangent
  const Vec3 V2 = dir(0.5f, 0.2f), L2 = dir(0.6f, 2.0f);
  const Vec3 V2w(V2.y, V2.z, V2.x), L2w(L2.y, L2.z, L2.x);  // into the N = +y world
  const SynthesizedShading a = shadeSynthesized(ndf, N, T, V2w, L2w, Vec3(0, 0, 1));
  const SynthesizedShading b = shadeSynthesized(swapped, N, T2, V2w, L2w, Vec3(0, 0, 1));
  EXPECT_NEAR(a.specular, b.specular, 1e-4f * a.specular);
}

TEST(SynthesizedShading, NeverNanAtGrazingOrDegenerateInput) {
  for (float alpha : {1e-4f, 0.3f, 1e4f}) {
    const BeckmannNdf ndf(alpha);
    const Vec3 N(0, 0, 1);
    for (Vec3 T : {Vec3(1, 0, 0), Vec3(0, 0, 1), Vec3(0.0f), Vec3(0, 0, -5)})
      for (float tv : {0.0f, 1.0f, 1.5707f, 1.5707963f, 1.6f})
        for (float tl : {0.0f, 1.2f, 1.5707963f})
          for (float pl : {0.0f, 3.14159265f})
            for (Vec3 m : {Vec3(0, 0, 1), glm::normalize(Vec3(0.99f, 0.0f, 1e-3f)),
                           Vec3(1e-4f, 0.0f, 1.0f)}) {
              const SynthesizedShading s =
                  shadeSynthesized(ndf, N, T, dir(tv, 0.0f), dir(tl, pl), m);
              ASSERT_TRUE(std::isfinite(s.specular) && std::isfinite(s.diffuse))
                  << alpha << " " << tv << " " << tl << " " << pl;
              EXPECT_GE(s.specular, 0.0f);
              EXPECT_GE(s.diffuse, 0.0f);
            }
    // V = -L: no half vector. Light below the surface: nothing.
    EXPECT_EQ(
        shadeSynthesized(ndf, N, Vec3(1, 0, 0), dir(1.0f, 0.0f), -dir(1.0f, 0.0f), Vec3(0, 0, 1))
            .specular,
        0.0f);
    const SynthesizedShading below =
        shadeSynthesized(ndf, N, Vec3(1, 0, 0), dir(0.3f, 0.0f), dir(1.8f, 1.0f), Vec3(0, 0, 1));
    EXPECT_EQ(below.specular, 0.0f);
    EXPECT_EQ(below.diffuse, 0.0f);
  }
}

}  // namespace
}  // namespace meso
