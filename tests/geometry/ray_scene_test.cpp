#include "meso/geometry/ray_scene.h"

#include "geometry/test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <span>
#include <stdexcept>
#include <thread>
#include <vector>

namespace meso {
namespace {

Vec3 randomDirection(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float z = 1.0f - 2.0f * u(rng), phi = 2.0f * kPi * u(rng);
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

// Embree's WatertightTest: rays from inside a closed surface must all hit it. Each hit's patch
// coordinates must also lead back to the limit surface near the hit (within the chord error).
void expectWatertight(const ControlMesh& control, int rate, int numRays) {
  const LimitSurface surface(control, SubdivisionScheme::CatmullClark);
  const TessellatedMesh mesh = tessellateUniform(surface, rate);
  RayScene scene;
  scene.addMesh(mesh);
  scene.commit();
  std::mt19937 rng(1234);
  int escapes = 0;
  float maxDistance = 0.0f;
  for (int i = 0; i < numRays; ++i) {
    const Ray ray{Vec3(0.0f), randomDirection(rng)};
    RayHit hit;
    if (!scene.intersect(ray, hit)) {
      ++escapes;
      continue;
    }
    const Vec2 st = mesh.patchCoords(hit.triangle, hit.b1, hit.b2);
    const Vec3 onLimit = surface.evaluate(mesh.triangleFace[hit.triangle], st).P;
    maxDistance = std::max(maxDistance, glm::length(onLimit - hit.t * ray.direction));
  }
  EXPECT_EQ(escapes, 0) << "rate " << rate;
  // Linear interpolation of st inside a triangle is second-order accurate: O(1 / rate^2).
  EXPECT_LT(maxDistance, 1.2f / static_cast<float>(rate * rate)) << "rate " << rate;
}

TEST(RayScene, RaysFromInsideClosedSurfacesNeverEscape) {
  expectWatertight(test::cube(), 5, 20000);
  expectWatertight(test::mixedPrism(), 5, 20000);
  expectWatertight(test::mixedPrism(), 2, 20000);
  expectWatertight(test::mixedPrism(), 16, 20000);
}

// A flat bilinear quad z = 1 over [0, 2] x [0, 3]: P(s, t) = (2 s, 3 t, 1).
TEST(RayScene, VerticalRayHitsFlatQuadAtAnalyticPoint) {
  ControlMesh quad;
  quad.positions = {Vec3(0, 0, 1), Vec3(2, 0, 1), Vec3(2, 3, 1), Vec3(0, 3, 1)};
  test::addFace(quad, {0, 1, 2, 3});
  const LimitSurface surface(quad, SubdivisionScheme::Bilinear);
  const TessellatedMesh mesh = tessellateUniform(surface, 3);
  RayScene scene;
  ASSERT_EQ(scene.addMesh(mesh), 0);
  scene.commit();
  EXPECT_EQ(scene.numTriangles(), mesh.numTriangles());
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.01f, 0.99f);
  for (int i = 0; i < 200; ++i) {
    const Vec2 st(u(rng), u(rng));
    RayHit hit;
    ASSERT_TRUE(scene.intersect(Ray{Vec3(2.0f * st.x, 3.0f * st.y, 5.0f), Vec3(0, 0, -1)}, hit));
    EXPECT_NEAR(hit.t, 4.0f, 1e-5f);
    EXPECT_EQ(hit.mesh, 0);
    ASSERT_GE(hit.triangle, 0);
    const Vec2 found = mesh.patchCoords(hit.triangle, hit.b1, hit.b2);
    EXPECT_LT(glm::length(found - st), 1e-5f) << st.x << "," << st.y;
    EXPECT_LT(glm::length(surface.evaluate(mesh.triangleFace[hit.triangle], found).P -
                          Vec3(2.0f * st.x, 3.0f * st.y, 1.0f)),
              1e-5f);
  }
}

TEST(RayScene, MissesAndRayIntervalsAreRespected) {
  ControlMesh quad = test::grid(1);
  RayScene scene;
  scene.addMesh(tessellateUniform(LimitSurface(quad, SubdivisionScheme::Bilinear), 1));
  scene.commit();
  RayHit hit;
  EXPECT_FALSE(scene.intersect(Ray{Vec3(0.5f, 0.5f, 1.0f), Vec3(0, 0, 1)}, hit));   // away
  EXPECT_FALSE(scene.intersect(Ray{Vec3(3.0f, 0.5f, 1.0f), Vec3(0, 0, -1)}, hit));  // beside
  EXPECT_FALSE(scene.intersect(Ray{Vec3(0.5f, 0.5f, 1.0f), Vec3(0, 0, -1), 0.0f, 0.9f}, hit));
  EXPECT_FALSE(scene.intersect(Ray{Vec3(0.5f, 0.5f, 1.0f), Vec3(0, 0, -1), 1.1f}, hit));
  EXPECT_TRUE(scene.intersect(Ray{Vec3(0.5f, 0.5f, 1.0f), Vec3(0, 0, -1), 0.0f, 1.1f}, hit));
  EXPECT_NEAR(hit.t, 1.0f, 1e-6f);
}

// occluded() agrees with intersect() on the interval [tNear, tFar], on triangles and on grids.
TEST(RayScene, OccludedMatchesIntersectOnTheRayInterval) {
  ControlMesh quad = test::grid(1);
  RayScene scene;
  scene.addMesh(tessellateUniform(LimitSurface(quad, SubdivisionScheme::Bilinear), 1));
  scene.commit();
  EXPECT_FALSE(scene.occluded(Ray{Vec3(0.5f, 0.5f, 1.0f), Vec3(0, 0, 1)}));
  EXPECT_FALSE(scene.occluded(Ray{Vec3(3.0f, 0.5f, 1.0f), Vec3(0, 0, -1)}));
  EXPECT_FALSE(scene.occluded(Ray{Vec3(0.5f, 0.5f, 1.0f), Vec3(0, 0, -1), 0.0f, 0.9f}));
  EXPECT_FALSE(scene.occluded(Ray{Vec3(0.5f, 0.5f, 1.0f), Vec3(0, 0, -1), 1.1f}));
  EXPECT_TRUE(scene.occluded(Ray{Vec3(0.5f, 0.5f, 1.0f), Vec3(0, 0, -1), 0.0f, 1.1f}));
  EXPECT_TRUE(scene.occluded(Ray{Vec3(0.5f, 0.5f, -1.0f), Vec3(0, 0, 1)}));  // either side
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-0.5f, 1.5f);
  RayHit hit;
  for (int i = 0; i < 2000; ++i) {
    const Ray ray{Vec3(u(rng), u(rng), 1.0f), randomDirection(rng)};
    EXPECT_EQ(scene.occluded(ray), scene.intersect(ray, hit)) << i;
  }
}

TEST(RayScene, MeshIndicesAreGeometryIdsAndDataIsCopied) {
  RayScene scene;
  {
    // The tessellations are destroyed right after addMesh: Embree must hold copies.
    ControlMesh near = test::grid(1), far = test::grid(1), empty;
    for (Vec3& p : far.positions) p.z = -2.0f;
    EXPECT_EQ(scene.addMesh(tessellateUniform(LimitSurface(near, SubdivisionScheme::Bilinear), 2)),
              0);
    EXPECT_EQ(scene.addMesh(TessellatedMesh{}), 1);  // empty meshes keep their index
    EXPECT_EQ(scene.addMesh(tessellateUniform(LimitSurface(far, SubdivisionScheme::Bilinear), 2)),
              2);
  }
  scene.commit();
  EXPECT_EQ(scene.numTriangles(), 16u);
  RayHit hit;
  ASSERT_TRUE(scene.intersect(Ray{Vec3(0.3f, 0.6f, 1.0f), Vec3(0, 0, -1)}, hit));
  EXPECT_EQ(hit.mesh, 0);
  EXPECT_NEAR(hit.t, 1.0f, 1e-6f);
  ASSERT_TRUE(scene.intersect(Ray{Vec3(0.3f, 0.6f, -1.0f), Vec3(0, 0, -1)}, hit));
  EXPECT_EQ(hit.mesh, 2);
  EXPECT_NEAR(hit.t, 1.0f, 1e-6f);
}

// A Catmull-Clark prism (mixed quads and triangles) tessellated at `rate`, committed.
void addPrism(RayScene& scene, int rate) {
  scene.addMesh(
      tessellateUniform(LimitSurface(test::mixedPrism(), SubdivisionScheme::CatmullClark), rate));
  scene.commit();
}

TEST(RayScene, ConcurrentQueriesMatchSerialOnes) {
  RayScene scene;
  addPrism(scene, 4);
  std::mt19937 rng(99);
  std::vector<Ray> rays(4000);
  for (Ray& r : rays) r = Ray{Vec3(0.1f, -0.2f, 0.05f), randomDirection(rng)};
  std::vector<RayHit> serial(rays.size()), parallel(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) scene.intersect(rays[i], serial[i]);
  std::vector<std::thread> threads;
  for (size_t w = 0; w < 4; ++w)
    threads.emplace_back([&, w] {
      for (size_t i = w; i < rays.size(); i += 4) scene.intersect(rays[i], parallel[i]);
    });
  for (std::thread& t : threads) t.join();
  for (size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(serial[i].triangle, parallel[i].triangle);
    ASSERT_EQ(serial[i].t, parallel[i].t);
  }
}

// The stream queries (one Embree ray stream, packets when coherent) answer each ray as the
// single-ray queries do: the same triangle and t to rounding, the same occlusion; spans longer
// than a stream chunk are traced in chunks, and a span shorter than the rays is refused.
TEST(RayScene, StreamQueriesMatchSingleRays) {
  RayScene scene;
  addPrism(scene, 6);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  // 2 chunks and a part; half the rays from inside (all hit), half from outside (some miss), a
  // third of them stopped short by tFar.
  std::vector<Ray> rays(2 * RayScene::kStreamChunk + 77);
  for (size_t i = 0; i < rays.size(); ++i) {
    const Vec3 from = i % 2 ? Vec3(0.1f, -0.2f, 0.05f) : Vec3(3.0f, 2.0f, 1.0f);
    rays[i] = Ray{from, randomDirection(rng)};
    if (i % 3 == 0) rays[i].tFar = 2.0f * u(rng);
  }
  for (const bool coherent : {true, false}) {
    std::vector<RayHit> hits(rays.size());
    std::vector<uint8_t> found(rays.size(), 7), occluded(rays.size(), 7);
    scene.intersect(rays, hits, found, coherent);
    scene.occluded(rays, occluded, coherent);
    int hitCount = 0, missCount = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      RayHit single;
      const bool hit = scene.intersect(rays[i], single);
      ASSERT_EQ(found[i], hit ? 1 : 0) << "ray " << i;
      EXPECT_EQ(occluded[i], scene.occluded(rays[i]) ? 1 : 0) << "ray " << i;
      if (!hit) {
        ++missCount;
        continue;
      }
      ++hitCount;
      EXPECT_EQ(hits[i].mesh, single.mesh);
      EXPECT_EQ(hits[i].triangle, single.triangle) << "ray " << i;
      EXPECT_NEAR(hits[i].t, single.t, 1e-5f * single.t) << "ray " << i;
      EXPECT_NEAR(hits[i].b1, single.b1, 1e-4f) << "ray " << i;
      EXPECT_NEAR(hits[i].b2, single.b2, 1e-4f) << "ray " << i;
      EXPECT_NEAR(glm::length(hits[i].Ng - single.Ng), 0.0f, 1e-4f * glm::length(single.Ng));
    }
    EXPECT_GT(hitCount, 200);
    EXPECT_GT(missCount, 50);
  }
  std::vector<RayHit> fewer(rays.size() - 1);
  std::vector<uint8_t> found(rays.size());
  EXPECT_THROW(scene.intersect(rays, fewer, found), std::invalid_argument);
  EXPECT_THROW(scene.occluded(rays, std::span<uint8_t>(found.data(), 3)), std::invalid_argument);
}

}  // namespace
}  // namespace meso
