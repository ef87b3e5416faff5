#include "meso/geometry/uv_speed.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace meso {
namespace {

// Three unit quads in a row (x = 0 .. 3), their u running at 1, 0.5 and 1 per unit of x: the length
// per unit of u is 1, 2 and 1 face by face and jumps at the edges x = 1 and x = 2. UvSpeed takes
// the mean at each vertex (1.5 on those edges) and interpolates it, so that both faces agree on
// their shared edge, and every face's corners bound it.
TEST(UvSpeed, IsContinuousAcrossFacesWhoseUvScalesDiffer) {
  ControlMesh mesh;
  const float us[] = {0.0f, 1.0f, 1.5f, 2.5f};
  for (int row = 0; row < 2; ++row)
    for (int i = 0; i < 4; ++i) {
      mesh.positions.emplace_back(static_cast<float>(i), static_cast<float>(row), 0.0f);
      mesh.uvs.emplace_back(us[i], static_cast<float>(row));
    }
  for (int f = 0; f < 3; ++f) {
    test::addFace(mesh, {f, f + 1, f + 5, f + 4});
    mesh.uvIndices.insert(mesh.uvIndices.end(), {f, f + 1, f + 5, f + 4});
  }
  const LimitSurface surface(mesh, SubdivisionScheme::Bilinear);
  const UvSpeed speed(mesh, surface);
  ASSERT_FALSE(speed.empty());
  // The point's own length jumps from 1 to 2 across x = 1.
  const auto own = [&](int face, Vec2 st) {
    const SurfacePoint sp = surface.evaluate(face, st);
    return std::max(glm::length(sp.Pu), glm::length(sp.Pv));
  };
  // Patch coordinates of the point a fraction t from corner a to corner b of a face.
  const auto along = [&](int face, int a, int b, float t) {
    return surface.cornerSt(face, a) + t * (surface.cornerSt(face, b) - surface.cornerSt(face, a));
  };
  // Face 0's corners 1 -> 2 are vertices 1 -> 5; face 1's corners 0 -> 3 are the same.
  for (float t : {0.0f, 0.3f, 0.5f, 1.0f}) {
    EXPECT_NEAR(own(0, along(0, 1, 2, t)), 1.0f, 1e-4f);
    EXPECT_NEAR(own(1, along(1, 0, 3, t)), 2.0f, 1e-4f);
    EXPECT_NEAR(speed.at(0, along(0, 1, 2, t)), 1.5f, 1e-5f) << t;
    EXPECT_NEAR(speed.at(1, along(1, 0, 3, t)), 1.5f, 1e-5f) << t;
  }
  // A vertex of one face alone keeps that face's length; between, the interpolation is linear.
  EXPECT_NEAR(speed.at(0, surface.cornerSt(0, 0)), 1.0f, 1e-5f);
  EXPECT_NEAR(speed.at(0, along(0, 0, 1, 0.5f)), 1.25f, 1e-5f);
  EXPECT_NEAR(speed.at(1, along(1, 0, 1, 0.5f)), 1.5f, 1e-5f);
  EXPECT_NEAR(speed.faceMax(0), 1.5f, 1e-5f);
  EXPECT_NEAR(speed.faceMax(1), 1.5f, 1e-5f);
  // Outside the faces: nothing.
  EXPECT_EQ(speed.at(-1, Vec2(0.5f)), 0.0f);
  EXPECT_EQ(speed.at(3, Vec2(0.5f)), 0.0f);
  EXPECT_EQ(UvSpeed().at(0, Vec2(0.5f)), 0.0f);
}

// A strip of 300 unit quads whose u runs at 1 per unit of x and at 0.5 in alternate runs of 10
// faces: runs of equal faces, whose corner lengths UvSpeed takes over from the face before
// (DerivativeSweep), and many changes of key within the ranges the faces are swept in. Every
// vertex still gets the mean of its faces' own lengths at it.
TEST(UvSpeed, RunsOfEqualFacesGiveTheMeansOfTheirOwnLengths) {
  constexpr int kFaces = 300;
  ControlMesh mesh;
  std::vector<float> u(kFaces + 1, 0.0f);
  for (int i = 0; i < kFaces; ++i) u[i + 1] = u[i] + ((i / 10) % 2 == 1 ? 0.5f : 1.0f);
  for (int row = 0; row < 2; ++row)
    for (int i = 0; i <= kFaces; ++i) {
      mesh.positions.emplace_back(static_cast<float>(i), static_cast<float>(row), 0.0f);
      mesh.uvs.emplace_back(u[i], static_cast<float>(row));
    }
  const int n = kFaces + 1;
  for (int f = 0; f < kFaces; ++f) {
    test::addFace(mesh, {f, f + 1, f + n + 1, f + n});
    mesh.uvIndices.insert(mesh.uvIndices.end(), {f, f + 1, f + n + 1, f + n});
  }
  const LimitSurface surface(mesh, SubdivisionScheme::Bilinear);
  const UvSpeed speed(mesh, surface);
  ASSERT_FALSE(speed.empty());
  const auto own = [&](int face, int corner) {
    const SurfacePoint sp = surface.evaluate(face, surface.cornerSt(face, corner));
    return std::max(glm::length(sp.Pu), glm::length(sp.Pv));
  };
  for (int f = 0; f < kFaces; ++f) {
    // Corners 0 and 3 lie on the edge shared with face f - 1, corners 1 and 2 with face f + 1.
    for (int k = 0; k < 4; ++k) {
      const int neighbour = k == 0 || k == 3 ? f - 1 : f + 1;
      const int corner = k == 0 ? 1 : k == 3 ? 2 : k == 1 ? 0 : 3;  // the same vertex there
      float expected = own(f, k);
      if (neighbour >= 0 && neighbour < kFaces)
        expected = 0.5f * (expected + own(neighbour, corner));
      EXPECT_NEAR(speed.at(f, surface.cornerSt(f, k)), expected, 1e-6f) << f << " " << k;
    }
  }
  EXPECT_NEAR(own(17, 0), 2.0f, 1e-5f);  // u at 0.5 per unit of x: 2 units per unit of u
  EXPECT_NEAR(speed.at(10, surface.cornerSt(10, 0)), 1.5f, 1e-5f);
}

// On a Catmull-Clark cube (no uv: each face's own (s, t) chart) every value is finite and positive,
// and on each face lies within its corners' range.
TEST(UvSpeed, IsFiniteAndBoundedByItsCornersOnACurvedSurface) {
  const ControlMesh mesh = test::cube();
  const LimitSurface surface(mesh, SubdivisionScheme::CatmullClark);
  const UvSpeed speed(mesh, surface);
  for (int f = 0; f < surface.numFaces(); ++f)
    for (float s : {0.0f, 0.25f, 0.5f, 1.0f})
      for (float t : {0.0f, 0.7f, 1.0f}) {
        const float v = speed.at(f, Vec2(s, t));
        EXPECT_TRUE(std::isfinite(v));
        EXPECT_GT(v, 0.0f);
        EXPECT_LE(v, speed.faceMax(f) * (1.0f + 1e-6f));
      }
}

// A unit quad (x = 0 .. 1) and a triangle beside it (x = 1 .. 3) whose u runs at half the rate:
// the triangle's corners on the shared edge take the vertex means, its own corner its own length,
// and between them at() is barycentric in the triangle's patch coordinates. A grid of quads keeps
// 21 bytes a face (first corner, four corner values, kind).
TEST(UvSpeed, IsBarycentricOverTrianglesAndSmallOverQuads) {
  ControlMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {3, 0.5f, 0}};
  mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {2, 0.5f}};
  test::addFace(mesh, {0, 1, 2, 3});
  test::addFace(mesh, {1, 4, 2});
  mesh.uvIndices = {0, 1, 2, 3, 1, 4, 2};
  const LimitSurface surface(mesh, SubdivisionScheme::Bilinear);
  const UvSpeed speed(mesh, surface);
  const auto own = [&](int face, Vec2 st) {
    const SurfacePoint sp = surface.evaluate(face, st);
    return std::max(glm::length(sp.Pu), glm::length(sp.Pv));
  };
  float corner[3];
  for (int k = 0; k < 3; ++k) {
    corner[k] = speed.at(1, surface.cornerSt(1, k));
    EXPECT_GT(corner[k], 0.0f);
  }
  // Corner 1 is the triangle's alone; corners 0 and 2 the means with the quad's.
  EXPECT_NEAR(corner[1], own(1, surface.cornerSt(1, 1)), 1e-5f);
  EXPECT_NEAR(corner[0], 0.5f * (own(0, surface.cornerSt(0, 1)) + own(1, surface.cornerSt(1, 0))),
              1e-5f);
  for (const Vec3 b : {Vec3(0.2f, 0.3f, 0.5f), Vec3(1.0f / 3.0f), Vec3(0.5f, 0.5f, 0.0f)}) {
    const Vec2 st =
        b.x * surface.cornerSt(1, 0) + b.y * surface.cornerSt(1, 1) + b.z * surface.cornerSt(1, 2);
    EXPECT_NEAR(speed.at(1, st), b.x * corner[0] + b.y * corner[1] + b.z * corner[2], 1e-5f);
  }
  const ControlMesh quads = test::grid(20);
  const UvSpeed quadSpeed(quads, LimitSurface(quads, SubdivisionScheme::Bilinear));
  EXPECT_LE(quadSpeed.memoryBytes(), 21u * 400u + 4u);
  EXPECT_NEAR(quadSpeed.at(7, Vec2(0.3f, 0.6f)), 1.0f, 1e-6f);  // unit quads: 1 everywhere
}

}  // namespace
}  // namespace meso
