#include "meso/geometry/tessellation.h"

#include "geometry/test_meshes.h"
#include "meso/core/error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace meso {
namespace {

using Edge = std::pair<uint32_t, uint32_t>;

// Triangles of each undirected edge, with the edge's direction in that triangle.
struct EdgeUse {
  size_t triangle;
  bool forward;  // the triangle runs from the smaller to the larger vertex index
};

std::map<Edge, std::vector<EdgeUse>> edgeUses(const TessellatedMesh& mesh) {
  std::map<Edge, std::vector<EdgeUse>> uses;
  for (size_t t = 0; t < mesh.numTriangles(); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = mesh.indices[3 * t + k], b = mesh.indices[3 * t + (k + 1) % 3];
      uses[{std::min(a, b), std::max(a, b)}].push_back({t, a < b});
    }
  return uses;
}

Vec3 facetNormal(const TessellatedMesh& mesh, size_t t) {
  const Vec3 a = mesh.positions[mesh.indices[3 * t]], b = mesh.positions[mesh.indices[3 * t + 1]],
             c = mesh.positions[mesh.indices[3 * t + 2]];
  return glm::normalize(glm::cross(b - a, c - a));
}

// Embree barycentrics (b1, b2) of the point halfway between vertices a and b of triangle t.
Vec2 midpointBarycentrics(const TessellatedMesh& mesh, size_t t, uint32_t a, uint32_t b) {
  float w[3];
  for (int k = 0; k < 3; ++k) {
    const uint32_t v = mesh.indices[3 * t + k];
    w[k] = (v == a || v == b) ? 0.5f : 0.0f;
  }
  return Vec2(w[1], w[2]);
}

TEST(Tessellation, RateBelowOneThrows) {
  const LimitSurface surface(test::cube(), SubdivisionScheme::CatmullClark);
  EXPECT_THROW(tessellateUniform(surface, 0), Error);
  EXPECT_THROW(tessellateUniform(surface, -3), Error);
}

TEST(Tessellation, CubeCountsShareEveryBoundaryPoint) {
  const LimitSurface surface(test::cube(), SubdivisionScheme::CatmullClark);
  for (int rate : {1, 2, 4, 5}) {
    const TessellatedMesh mesh = tessellateUniform(surface, rate);
    // A closed surface of 12 R^2 triangles has 18 R^2 edges and, by Euler, 6 R^2 + 2 vertices:
    // exactly the count when corner and edge points are not duplicated.
    EXPECT_EQ(mesh.numTriangles(), size_t(12 * rate * rate));
    EXPECT_EQ(mesh.positions.size(), size_t(6 * rate * rate + 2));
    EXPECT_EQ(mesh.indices.size(), 3 * mesh.numTriangles());
    EXPECT_EQ(mesh.cornerSt.size(), 3 * mesh.numTriangles());
  }
}

// Every edge is used by exactly two triangles, once in each direction: closed (no cracks) and
// consistently oriented, on quads, triangles and pentagons, at odd and even rates.
TEST(Tessellation, ClosedMeshesStayClosedAndOriented) {
  for (const ControlMesh& control : {test::cube(), test::mixedPrism()})
    for (int rate = 1; rate <= 6; ++rate) {
      const TessellatedMesh mesh =
          tessellateUniform(LimitSurface(control, SubdivisionScheme::CatmullClark), rate);
      for (const auto& [edge, uses] : edgeUses(mesh)) {
        ASSERT_NE(edge.first, edge.second) << "degenerate triangle at rate " << rate;
        ASSERT_EQ(uses.size(), 2u)
            << "edge " << edge.first << "-" << edge.second << " rate " << rate;
        EXPECT_NE(uses[0].forward, uses[1].forward) << "rate " << rate;
      }
    }
}

TEST(Tessellation, CornerCoordinatesReproduceVertices) {
  for (const ControlMesh& control : {test::cube(), test::mixedPrism()})
    for (int rate : {1, 3, 4}) {
      const LimitSurface surface(control, SubdivisionScheme::CatmullClark);
      const TessellatedMesh mesh = tessellateUniform(surface, rate);
      for (size_t t = 0; t < mesh.numTriangles(); ++t)
        for (int k = 0; k < 3; ++k) {
          const Vec3 p = surface.evaluate(mesh.triangleFace[t], mesh.cornerSt[3 * t + k]).P;
          ASSERT_LT(glm::length(p - mesh.positions[mesh.indices[3 * t + k]]), 1e-5f)
              << "triangle " << t << " corner " << k << " rate " << rate;
        }
    }
}

TEST(Tessellation, FacetNormalsAgreeWithLimitNormals) {
  for (const ControlMesh& control : {test::cube(), test::mixedPrism()})
    for (int rate : {1, 2, 5}) {
      const LimitSurface surface(control, SubdivisionScheme::CatmullClark);
      const TessellatedMesh mesh = tessellateUniform(surface, rate);
      for (size_t t = 0; t < mesh.numTriangles(); ++t) {
        const Vec3 n =
            surface.evaluate(mesh.triangleFace[t], mesh.patchCoords(t, 1.0f / 3, 1.0f / 3)).N;
        EXPECT_GT(glm::dot(facetNormal(mesh, t), n), 0.5f) << "triangle " << t << " rate " << rate;
      }
    }
}

// Limit normals at the midpoint of a shared edge, evaluated from each triangle's own barycentrics
// (and, across patch boundaries, in each triangle's own face), and the angle between the facets.
struct EdgeNormals {
  float maxLimitJump = 0.0f;
  float meanFacetAngle = 0.0f;
};

EdgeNormals compareAcrossEdges(const LimitSurface& surface, const TessellatedMesh& mesh) {
  EdgeNormals result;
  int pairs = 0;
  for (const auto& [edge, uses] : edgeUses(mesh)) {
    const size_t t1 = uses[0].triangle, t2 = uses[1].triangle;
    const Vec2 b1 = midpointBarycentrics(mesh, t1, edge.first, edge.second);
    const Vec2 b2 = midpointBarycentrics(mesh, t2, edge.first, edge.second);
    const Vec3 n1 = surface.evaluate(mesh.triangleFace[t1], mesh.patchCoords(t1, b1.x, b1.y)).N;
    const Vec3 n2 = surface.evaluate(mesh.triangleFace[t2], mesh.patchCoords(t2, b2.x, b2.y)).N;
    result.maxLimitJump = std::max(result.maxLimitJump, glm::length(n1 - n2));
    const float cosine = glm::dot(facetNormal(mesh, t1), facetNormal(mesh, t2));
    result.meanFacetAngle += std::acos(std::clamp(cosine, -1.0f, 1.0f));
    ++pairs;
  }
  result.meanFacetAngle /= static_cast<float>(std::max(pairs, 1));
  return result;
}

// Chan 2002: shading from the limit normal is continuous across triangle edges (inside a patch and
// between patches), while facet normals jump by an angle that only shrinks with refinement.
TEST(Tessellation, ShadingNormalsAreContinuousAcrossTriangleEdges) {
  for (const ControlMesh& control : {test::cube(), test::mixedPrism()}) {
    const LimitSurface surface(control, SubdivisionScheme::CatmullClark);
    float previousAngle = 1e9f;
    for (int rate : {2, 4, 8, 16}) {
      const EdgeNormals e = compareAcrossEdges(surface, tessellateUniform(surface, rate));
      EXPECT_LT(e.maxLimitJump, 1e-5f) << "rate " << rate;
      EXPECT_LT(e.meanFacetAngle, previousAngle) << "rate " << rate;
      EXPECT_GT(e.meanFacetAngle, 100.0f * std::max(e.maxLimitJump, 1e-6f)) << "rate " << rate;
      previousAngle = e.meanFacetAngle;
    }
  }
}

TEST(Tessellation, CollapsedFacesGiveFinitePoints) {
  ControlMesh collapsed = test::grid(3);
  for (int v : {5, 6, 9, 10}) collapsed.positions[v] = Vec3(1.5f, 1.5f, 0.0f);
  ControlMesh repeated = test::grid(2);
  repeated.faceVertices[2] = repeated.faceVertices[3];  // a quad with a repeated vertex
  for (const ControlMesh& control : {collapsed, repeated}) {
    const TessellatedMesh mesh =
        tessellateUniform(LimitSurface(control, SubdivisionScheme::CatmullClark), 4);
    EXPECT_GT(mesh.numTriangles(), 0u);
    for (const Vec3& p : mesh.positions) ASSERT_TRUE(isFinite(p));
    for (uint32_t i : mesh.indices) ASSERT_LT(i, mesh.positions.size());
  }
}

}  // namespace
}  // namespace meso
