#include "meso/geometry/limit_surface.h"

#include "geometry/test_meshes.h"
#include "meso/core/error.h"
#include "meso/core/huge_pages.h"

#include <gtest/gtest.h>
#include <malloc.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <set>
#include <vector>

namespace meso {
namespace {

// st of corner k of a quad face (Bfr's quad parameterization).
Vec2 quadCorner(int k) { return Vec2(k == 1 || k == 2 ? 1.0f : 0.0f, k >= 2 ? 1.0f : 0.0f); }

bool finitePoint(const SurfacePoint& sp) {
  return isFinite(sp.P) && isFinite(sp.Pu) && isFinite(sp.Pv) && isFinite(sp.N) &&
         std::isfinite(sp.uv.x) && std::isfinite(sp.uv.y) &&
         std::abs(glm::length(sp.N) - 1.0f) < 1e-4f;
}

// Samples of the face domain: a grid over the unit square, or over the unit right triangle.
std::vector<Vec2> domainSamples(int n, bool triangle) {
  std::vector<Vec2> st;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      if (!triangle || i + j <= n) st.emplace_back(float(i) / n, float(j) / n);
  return st;
}

TEST(LimitSurface, FlatGridStaysFlat) {
  const LimitSurface surface(test::grid(4), SubdivisionScheme::CatmullClark);
  ASSERT_EQ(surface.numFaces(), 16);
  for (int f = 0; f < surface.numFaces(); ++f) {
    ASSERT_TRUE(surface.hasLimitSurface(f));
    EXPECT_EQ(surface.faceSize(f), 4);
    for (Vec2 st : domainSamples(8, false)) {
      const SurfacePoint sp = surface.evaluate(f, st);
      ASSERT_NEAR(sp.P.z, 0.0f, 1e-6f) << "face " << f << " st " << st.x << "," << st.y;
      ASSERT_LT(glm::length(sp.N - Vec3(0.0f, 0.0f, 1.0f)), 1e-5f) << "face " << f;
      EXPECT_EQ(sp.uv, st);
    }
  }
}

// The Catmull-Clark limit position of a vertex of valence n (Halstead et al. 1993):
// P = (n^2 V + 4 sum(edge neighbours) + sum(diagonal face vertices)) / (n (n + 5)).
Vec3 valenceLimitPoint(const ControlMesh& mesh, int vertex) {
  std::set<int> edgeNeighbours;
  Vec3 diagonal(0.0f);
  int n = 0, first = 0;
  for (int f = 0; f < mesh.numFaces(); first += mesh.faceSizes[f], ++f) {
    const int* v = &mesh.faceVertices[first];
    for (int k = 0; k < 4; ++k) {
      if (v[k] != vertex) continue;
      ++n;
      edgeNeighbours.insert(v[(k + 1) % 4]);
      edgeNeighbours.insert(v[(k + 3) % 4]);
      diagonal += mesh.positions[v[(k + 2) % 4]];
    }
  }
  Vec3 edges(0.0f);
  for (int e : edgeNeighbours) edges += mesh.positions[e];
  const float fn = static_cast<float>(n);
  return (fn * fn * mesh.positions[vertex] + 4.0f * edges + diagonal) / (fn * (fn + 5.0f));
}

TEST(LimitSurface, CubeCornersMatchValenceFormula) {
  const ControlMesh mesh = test::cube();
  const LimitSurface surface(mesh, SubdivisionScheme::CatmullClark);
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 4; ++k) {
      const int vertex = mesh.faceVertices[4 * f + k];
      const Vec3 expected = valenceLimitPoint(mesh, vertex);
      EXPECT_NEAR(glm::length(expected), 0.5f * std::sqrt(3.0f), 1e-6f);  // (+-0.5, +-0.5, +-0.5)
      const SurfacePoint sp = surface.evaluate(f, quadCorner(k));
      EXPECT_LT(glm::length(sp.P - expected), 1e-5f) << "face " << f << " corner " << k;
      EXPECT_LT(glm::length(sp.N - glm::normalize(mesh.positions[vertex])), 1e-5f)
          << "face " << f << " corner " << k;
    }
}

// Faces are set up in parallel chunks of 1024, each keeping its arrays. On meshes of several chunks
// every face keeps its own patch: each corner of a refined cube (valence-3 corners: Bfr surfaces,
// shared through the factory's cache) is its vertex's limit point, and a bilinear uv grid's points
// and uv are the bilinear interpolation of its face's corners. The surfaces are the same bits with
// 1 thread and with 2.
TEST(LimitSurface, ChunkedSetUpKeepsEveryFacesPatchWhateverTheThreads) {
  const ControlMesh cube = test::refinedCube(24);  // 3 456 faces
  ControlMesh ground = test::grid(80);             // 6 400 faces
  for (const Vec3& p : ground.positions) ground.uvs.emplace_back(p.x / 80.0f, p.y / 160.0f);
  ground.uvIndices = ground.faceVertices;
  const struct {
    const ControlMesh& mesh;
    SubdivisionScheme scheme;
  } cases[] = {{cube, SubdivisionScheme::CatmullClark}, {ground, SubdivisionScheme::Bilinear}};
  for (const auto& c : cases) {
    std::vector<std::unique_ptr<LimitSurface>> built;
    for (int threads : {1, 2}) {
      tbb::task_arena arena(threads);
      arena.execute([&] { built.push_back(std::make_unique<LimitSurface>(c.mesh, c.scheme)); });
    }
    const LimitSurface& one = *built[0];
    const LimitSurface& two = *built[1];
    ASSERT_EQ(one.numFaces(), c.mesh.numFaces());
    EXPECT_EQ(one.memoryBytes(), two.memoryBytes());
    const bool bilinear = c.scheme == SubdivisionScheme::Bilinear;
    for (int f = 0; f < c.mesh.numFaces(); ++f) {
      const int* v = &c.mesh.faceVertices[4 * f];
      for (int k = 0; k < 4; ++k) {
        const SurfacePoint sp = one.evaluate(f, quadCorner(k));
        const Vec3 expected = bilinear ? c.mesh.positions[v[k]] : valenceLimitPoint(c.mesh, v[k]);
        ASSERT_LT(glm::length(sp.P - expected), 1e-5f) << "face " << f << " corner " << k;
      }
      for (Vec2 st : domainSamples(3, false)) {
        const SurfacePoint a = one.evaluate(f, st), b = two.evaluate(f, st);
        ASSERT_TRUE(a.P == b.P && a.Pu == b.Pu && a.Pv == b.Pv && a.N == b.N && a.uv == b.uv)
            << "face " << f;
        if (!bilinear) continue;
        const auto lerp = [&](const auto& at) {
          return (1.0f - st.y) * ((1.0f - st.x) * at(v[0]) + st.x * at(v[1])) +
                 st.y * ((1.0f - st.x) * at(v[3]) + st.x * at(v[2]));
        };
        ASSERT_LT(glm::length(a.P - lerp([&](int i) { return c.mesh.positions[i]; })), 1e-4f);
        ASSERT_LT(glm::length(a.uv - lerp([&](int i) { return c.mesh.uvs[i]; })), 1e-6f);
      }
    }
  }
}

// Catmull-Clark on a regular grid is the uniform bicubic B-spline of its points, with the points
// beyond a boundary edge reflected (2 P0 - P1, both ways at a corner). Interior, edge and corner
// faces have regular patches of different boundary masks, which faces of one kind share (a Bfr
// surface per kind and chunk): every face of a grid with random heights, in a mesh of two chunks,
// is its B-spline patch.
TEST(LimitSurface, RegularPatchesAreTheirBSplinePatches) {
  constexpr int n = 40;  // 1 600 faces
  ControlMesh mesh = test::grid(n);
  uint32_t seed = 12345u;
  for (Vec3& p : mesh.positions) {
    seed = seed * 1664525u + 1013904223u;
    p.z = float(seed >> 8) / float(1u << 24) - 0.5f;
  }
  const LimitSurface surface(mesh, SubdivisionScheme::CatmullClark);
  const auto point = [&](int i, int j) -> Vec3 {
    const auto reflect = [&](int k, int& inside, int& next) {
      inside = std::clamp(k, 0, n);
      next = k < 0 ? 1 : n - 1;
      return k < 0 || k > n;
    };
    int i0, i1, j0, j1;
    const bool ri = reflect(i, i0, i1), rj = reflect(j, j0, j1);
    const auto at = [&](int a, int b) { return Vec3(mesh.positions[b * (n + 1) + a]); };
    const auto column = [&](int a) { return rj ? 2.0f * at(a, j0) - at(a, j1) : at(a, j0); };
    return ri ? 2.0f * column(i0) - column(i1) : column(i0);
  };
  const auto basis = [](float u) {
    return std::array<float, 4>{(1 - u) * (1 - u) * (1 - u) / 6,
                                (3 * u * u * u - 6 * u * u + 4) / 6,
                                (-3 * u * u * u + 3 * u * u + 3 * u + 1) / 6, u * u * u / 6};
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      for (Vec2 st : domainSamples(3, false)) {
        const std::array<float, 4> bs = basis(st.x), bt = basis(st.y);
        Vec3 expected(0.0f);
        for (int b = 0; b < 4; ++b)
          for (int a = 0; a < 4; ++a) expected += bs[a] * bt[b] * point(i - 1 + a, j - 1 + b);
        const Vec3 p = surface.evaluate(j * n + i, st).P;
        ASSERT_LT(glm::length(p - expected), 2e-5f)
            << "face (" << i << ", " << j << ") at (" << st.x << ", " << st.y << ")";
      }
}

TEST(LimitSurface, CubeNormalsPointOutward) {
  const LimitSurface surface(test::cube(), SubdivisionScheme::CatmullClark);
  for (int f = 0; f < surface.numFaces(); ++f)
    for (Vec2 st : domainSamples(6, false)) {
      const SurfacePoint sp = surface.evaluate(f, st);
      ASSERT_TRUE(finitePoint(sp));
      // The limit of a cube is convex and centred on the origin.
      EXPECT_GT(glm::dot(sp.N, glm::normalize(sp.P)), 0.5f);
      EXPECT_LT(glm::length(glm::normalize(glm::cross(sp.Pu, sp.Pv)) - sp.N), 1e-4f);
    }
}

TEST(LimitSurface, LoopNeedsTriangles) {
  EXPECT_THROW(LimitSurface(test::cube(), SubdivisionScheme::Loop), Error);
  ControlMesh tetra;
  tetra.positions = {Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1)};
  test::addFace(tetra, {0, 1, 2});
  test::addFace(tetra, {0, 2, 3});
  test::addFace(tetra, {0, 3, 1});
  test::addFace(tetra, {1, 3, 2});
  const LimitSurface surface(tetra, SubdivisionScheme::Loop);
  for (int f = 0; f < 4; ++f) {
    EXPECT_EQ(surface.faceSize(f), 3);
    for (Vec2 st : domainSamples(6, true)) {
      const SurfacePoint sp = surface.evaluate(f, st);
      ASSERT_TRUE(finitePoint(sp));
      EXPECT_GT(glm::dot(sp.N, sp.P), 0.0f);  // outward on the convex limit
    }
  }
}

TEST(LimitSurface, MalformedMeshesThrow) {
  ControlMesh outOfRange = test::grid(1);
  outOfRange.faceVertices[2] = 17;
  EXPECT_THROW(LimitSurface(outOfRange, SubdivisionScheme::CatmullClark), Error);
  ControlMesh twoSided = test::grid(1);
  twoSided.faceSizes = {2, 2};
  EXPECT_THROW(LimitSurface(twoSided, SubdivisionScheme::Bilinear), Error);
  ControlMesh badUvs = test::grid(1);
  badUvs.uvs = {Vec2(0.0f)};
  badUvs.uvIndices = {0, 0, 0};
  EXPECT_THROW(LimitSurface(badUvs, SubdivisionScheme::CatmullClark), Error);
  EXPECT_THROW(LimitSurface(ControlMesh{}, SubdivisionScheme::CatmullClark), Error);
}

// uv = A (x, y) + b on a flat grid, so (x, y) = A^-1 (uv - b) and P_u, P_v are A^-1's columns.
TEST(LimitSurface, TextureDerivativesFollowTheChainRule) {
  const glm::mat2 a(glm::vec2(1.6f, 1.2f),
                    glm::vec2(-0.5f, 2.5f));  // columns: scale, rotation, shear
  const glm::vec2 b(0.3f, -0.7f);
  ControlMesh plain = test::grid(4);
  ControlMesh mapped = plain;
  for (const Vec3& p : mapped.positions) mapped.uvs.push_back(a * Vec2(p) + b);
  mapped.uvIndices = mapped.faceVertices;
  const LimitSurface withUv(mapped, SubdivisionScheme::CatmullClark);
  const LimitSurface withoutUv(plain, SubdivisionScheme::CatmullClark);
  const glm::mat2 ainv = glm::inverse(a);
  for (int f = 0; f < withUv.numFaces(); ++f)
    for (Vec2 st : domainSamples(4, false)) {
      const SurfacePoint sp = withUv.evaluate(f, st);
      const SurfacePoint ref = withoutUv.evaluate(f, st);
      EXPECT_LT(glm::length(sp.uv - (a * Vec2(ref.P) + b)), 1e-5f);
      EXPECT_LT(glm::length(sp.Pu - Vec3(ainv[0], 0.0f)), 1e-5f);
      EXPECT_LT(glm::length(sp.Pv - Vec3(ainv[1], 0.0f)), 1e-5f);
      // Chain rule against the patch derivatives: dP/ds = Pu du/ds + Pv dv/ds.
      const glm::mat2 duvdst = a * glm::mat2(Vec2(ref.Pu), Vec2(ref.Pv));
      EXPECT_LT(glm::length(ref.Pu - (sp.Pu * duvdst[0][0] + sp.Pv * duvdst[0][1])), 1e-5f);
      EXPECT_LT(glm::length(ref.Pv - (sp.Pu * duvdst[1][0] + sp.Pv * duvdst[1][1])), 1e-5f);
      EXPECT_LT(glm::length(sp.N - Vec3(0.0f, 0.0f, 1.0f)), 1e-5f);
    }
}

// A bilinear-scheme quad is the bilinear interpolation of its corners (evaluated directly, without
// Bfr's generic patch, since it is the hybrid's per-hit cost): a twisted, non-planar quad with a
// sheared, stretched uv map, so that every term of P, uv, P_u and P_v is exercised.
TEST(LimitSurface, BilinearQuadIsTheBilinearInterpolationOfItsCorners) {
  ControlMesh mesh;
  mesh.positions = {Vec3(0, 0, 0), Vec3(3, 0.2f, 0.5f), Vec3(2.5f, 1.5f, -0.4f),
                    Vec3(-0.3f, 1, 0.9f)};
  test::addFace(mesh, {0, 1, 2, 3});
  mesh.uvs = {Vec2(0.1f, 0.2f), Vec2(8.0f, 0.9f), Vec2(9.5f, 2.6f), Vec2(1.2f, 2.0f)};
  mesh.uvIndices = mesh.faceVertices;
  const LimitSurface surface(mesh, SubdivisionScheme::Bilinear);
  // Corner k sits at st = cornerSt(0, k); st is the bilinear parameter of the corners in that
  // order.
  std::array<Vec2, 4> at;
  for (int k = 0; k < 4; ++k) at[k] = surface.cornerSt(0, k);
  ASSERT_EQ(at[0], Vec2(0, 0));
  ASSERT_EQ(at[1], Vec2(1, 0));
  ASSERT_EQ(at[2], Vec2(1, 1));
  ASSERT_EQ(at[3], Vec2(0, 1));
  auto lerp4 = [](auto c0, auto c1, auto c2, auto c3, float s, float t) {
    return (1 - t) * ((1 - s) * c0 + s * c1) + t * ((1 - s) * c3 + s * c2);
  };
  const auto& p = mesh.positions;
  const auto& q = mesh.uvs;
  for (Vec2 st : domainSamples(6, false)) {
    const float s = st.x, t = st.y;
    const SurfacePoint sp = surface.evaluate(0, st);
    EXPECT_LT(glm::length(sp.P - lerp4(p[0], p[1], p[2], p[3], s, t)), 1e-5f);
    EXPECT_LT(glm::length(sp.uv - lerp4(q[0], q[1], q[2], q[3], s, t)), 1e-5f);
    const Vec3 dPds = (1 - t) * (p[1] - p[0]) + t * (p[2] - p[3]);
    const Vec3 dPdt = (1 - s) * (p[3] - p[0]) + s * (p[2] - p[1]);
    const Vec2 duvds = (1 - t) * (q[1] - q[0]) + t * (q[2] - q[3]);
    const Vec2 duvdt = (1 - s) * (q[3] - q[0]) + s * (q[2] - q[1]);
    EXPECT_LT(glm::length(dPds - (sp.Pu * duvds.x + sp.Pv * duvds.y)), 1e-4f);
    EXPECT_LT(glm::length(dPdt - (sp.Pu * duvdt.x + sp.Pv * duvdt.y)), 1e-4f);
    EXPECT_LT(glm::length(sp.N - glm::normalize(glm::cross(dPds, dPdt))), 1e-5f);
  }
}

// Every quad of a bilinear mesh that also has triangles, a pentagon, uv seams and three quads on
// one edge (a non-manifold fan, left to Bfr) is the bilinear quad of its corners and of their uv,
// whether prepared directly or by Bfr.
TEST(LimitSurface, BilinearQuadsOfAnyMeshAreTheBilinearPatchesOfTheirCorners) {
  ControlMesh mesh = test::grid(3);
  Rng rng(7);
  for (Vec3& p : mesh.positions) p += 0.2f * test::randomDirection(rng);
  const int n = static_cast<int>(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), {Vec3(1.2f, 0.4f, 2.0f), Vec3(0.3f, 1.1f, -1.5f),
                                               Vec3(2.2f, 2.5f, 1.0f), Vec3(-0.8f, 0.4f, 0.7f)});
  test::addFace(mesh, {0, 1, n});                // a triangle on the grid's boundary edge
  test::addFace(mesh, {1, 0, n + 1, n + 2});     // a quad on the same edge: three faces there
  test::addFace(mesh, {0, 4, n + 3});            // another triangle
  test::addFace(mesh, {3, n + 2, n + 1, 2, 7});  // a pentagon
  // Seams: each corner its own uv, from a map that folds nowhere.
  for (int f = 0, corner = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < mesh.faceSizes[f]; ++k, ++corner) {
      const Vec3& p = mesh.positions[mesh.faceVertices[corner]];
      mesh.uvs.emplace_back(0.5f * p.x + 0.1f * p.z + 0.3f * f, 0.7f * p.y - 0.2f * p.z);
      mesh.uvIndices.push_back(corner);
    }
  const LimitSurface surface(mesh, SubdivisionScheme::Bilinear);
  int quads = 0;
  for (int f = 0, first = 0; f < mesh.numFaces(); first += mesh.faceSizes[f++]) {
    ASSERT_TRUE(surface.hasLimitSurface(f)) << f;
    if (mesh.faceSizes[f] != 4) continue;
    ++quads;
    std::array<Vec3, 4> p;
    std::array<Vec2, 4> q;
    for (int k = 0; k < 4; ++k) {
      ASSERT_EQ(surface.cornerSt(f, k), quadCorner(k));
      p[k] = mesh.positions[mesh.faceVertices[first + k]];
      q[k] = mesh.uvs[mesh.uvIndices[first + k]];
    }
    for (Vec2 st : domainSamples(4, false)) {
      const float s = st.x, t = st.y;
      const SurfacePoint sp = surface.evaluate(f, st);
      const Vec3 P = (1 - t) * ((1 - s) * p[0] + s * p[1]) + t * ((1 - s) * p[3] + s * p[2]);
      const Vec2 uv = (1 - t) * ((1 - s) * q[0] + s * q[1]) + t * ((1 - s) * q[3] + s * q[2]);
      EXPECT_LT(glm::length(sp.P - P), 1e-5f) << f;
      EXPECT_LT(glm::length(sp.uv - uv), 1e-5f) << f;
      const Vec3 dPds = (1 - t) * (p[1] - p[0]) + t * (p[2] - p[3]);
      const Vec2 duvds = (1 - t) * (q[1] - q[0]) + t * (q[2] - q[3]);
      EXPECT_LT(glm::length(dPds - (sp.Pu * duvds.x + sp.Pv * duvds.y)), 1e-4f) << f;
    }
  }
  EXPECT_EQ(quads, 10);
}

// Faces of one derivative key evaluate to the same Pu, Pv and N, bit for bit: on a ground of
// unit quads whose uv is stretched in some rows and whose points are moved in others (a ground's
// faces repeat, a sculpted one's do not), with a triangle and a Catmull-Clark copy, which have no
// key.
TEST(LimitSurface, FacesOfOneDerivativeKeyEvaluateToTheSameDerivatives) {
  constexpr int kN = 8;
  ControlMesh mesh = test::grid(kN);
  Rng rng(11);
  // Rows 6 and up moved (no two faces alike), x scaled by 0.1 in rows 3 to 5 (the differences of
  // 0.1 i are not all the same float), unit squares below.
  for (Vec3& p : mesh.positions) {
    if (p.y >= 6.0f)
      p += 0.1f * test::randomDirection(rng);
    else if (p.y >= 3.0f)
      p.x *= 0.1f;
  }
  const int n = static_cast<int>(mesh.positions.size());
  mesh.positions.emplace_back(-1.0f, 0.5f, 0.2f);
  test::addFace(mesh, {0, n, kN + 1});
  // uv over the flat rows, stretched by 1.5 in u in rows 1 and 2: unit quads of two keys there.
  for (int f = 0, corner = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < mesh.faceSizes[f]; ++k, ++corner) {
      const Vec3& p = mesh.positions[mesh.faceVertices[corner]];
      const float stretch = f / kN == 1 || f / kN == 2 ? 1.5f : 1.0f;
      mesh.uvs.emplace_back(stretch * p.x + 0.25f * p.z, p.y);
      mesh.uvIndices.push_back(corner);
    }
  const LimitSurface surface(mesh, SubdivisionScheme::Bilinear);
  std::vector<DerivativeKey> keys(mesh.numFaces());
  std::vector<char> keyed(mesh.numFaces());
  for (int f = 0; f < mesh.numFaces(); ++f) keyed[f] = surface.derivativeKey(f, keys[f]);
  EXPECT_FALSE(keyed[mesh.numFaces() - 1]) << "a triangle";
  std::vector<Vec2> st = domainSamples(4, false);
  st.insert(st.end(), {Vec2(0.3f, 0.7f), Vec2(0.91f, 0.13f), Vec2(-0.2f, 1.4f)});
  const auto same = [](const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  int pairs = 0, unequal = 0;
  for (int f = 0; f < kN * kN; ++f) {
    ASSERT_TRUE(keyed[f]) << f;
    for (int g = f + 1; g < kN * kN; ++g) {
      if (!(keys[f] == keys[g])) {
        ++unequal;
        continue;
      }
      ++pairs;
      for (const Vec2 c : st) {
        const SurfacePoint a = surface.evaluate(f, c), b = surface.evaluate(g, c);
        ASSERT_TRUE(same(a.Pu, b.Pu) && same(a.Pv, b.Pv) && same(a.N, b.N))
            << "faces " << f << " and " << g << " at " << c.x << "," << c.y;
      }
    }
  }
  // Rows 0 and 1 are 8 unit squares each, of two uv keys: C(8,2) pairs each. Rows 3 and 4 add the
  // faces whose differences of 0.1 i round alike; rows 2 and 5 reach moved or scaled points.
  EXPECT_GE(pairs, 2 * 28);
  EXPECT_GT(unequal, pairs);
  // A sweep in face order takes over the last face it evaluated exactly where their keys agree.
  DerivativeSweep sweep(surface);
  int evaluated = -1, takenOver = 0;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const int same = sweep.sameAs(f);
    const bool expected = keyed[f] && evaluated >= 0 && keys[f] == keys[evaluated];
    ASSERT_EQ(same, expected ? evaluated : -1) << f;
    if (same >= 0) {
      ++takenOver;
    } else {
      evaluated = keyed[f] ? f : -1;
    }
  }
  // Rows 0 and 1: 7 faces each; rows 3 and 4 some.
  EXPECT_GE(takenOver, 14);
  // Without uv the key is the patch's alone; Catmull-Clark patches have none.
  ControlMesh plain = test::grid(3);
  const LimitSurface bilinear(plain, SubdivisionScheme::Bilinear);
  const LimitSurface smooth(plain, SubdivisionScheme::CatmullClark);
  DerivativeKey a, b;
  ASSERT_TRUE(bilinear.derivativeKey(0, a) && bilinear.derivativeKey(8, b));
  EXPECT_TRUE(a == b);
  for (int f = 0; f < smooth.numFaces(); ++f) EXPECT_FALSE(smooth.derivativeKey(f, a)) << f;
}

TEST(LimitSurface, UvScaledByTwoHalvesTheDerivatives) {
  ControlMesh mesh = test::grid(4);
  const LimitSurface plain(mesh, SubdivisionScheme::CatmullClark);
  for (const Vec3& p : mesh.positions) mesh.uvs.push_back(2.0f * Vec2(p));
  mesh.uvIndices = mesh.faceVertices;
  const LimitSurface scaled(mesh, SubdivisionScheme::CatmullClark);
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (Vec2 st : domainSamples(3, false)) {
      const SurfacePoint sp = scaled.evaluate(f, st), ref = plain.evaluate(f, st);
      EXPECT_NEAR(glm::length(sp.Pu), 0.5f * glm::length(ref.Pu), 1e-5f);
      EXPECT_NEAR(glm::length(sp.Pv), 0.5f * glm::length(ref.Pv), 1e-5f);
    }
}

// On a curved surface: Pu is the derivative of P along the direction in st where only u changes.
// The samples avoid the quarter of the face around each extraordinary corner: Bfr represents those
// regions by Gregory patches whose derivatives (as in Far) omit the derivative of the rational
// blending and differ from finite differences of P by about 1%.
TEST(LimitSurface, TextureDerivativesMatchFiniteDifferencesOnCube) {
  ControlMesh mesh = test::cube();
  // Per face a rotated, non-uniformly scaled copy of the unit square: a different uv map per face.
  for (int f = 0; f < 6; ++f) {
    const float angle = 0.4f * f, su = 1.0f + 0.3f * f, sv = 0.5f + 0.1f * f;
    const glm::mat2 m =
        glm::mat2(std::cos(angle), std::sin(angle), -std::sin(angle), std::cos(angle)) *
        glm::mat2(su, 0.0f, 0.0f, sv);
    for (int k = 0; k < 4; ++k) {
      mesh.uvs.push_back(m * quadCorner(k) + Vec2(float(f)));
      mesh.uvIndices.push_back(4 * f + k);
    }
  }
  const LimitSurface surface(mesh, SubdivisionScheme::CatmullClark);
  const float h = 1e-3f;
  for (int f = 0; f < 6; ++f)
    for (Vec2 st : {Vec2(0.5f), Vec2(0.2f, 0.7f), Vec2(0.6f, 0.3f)}) {
      const SurfacePoint sp = surface.evaluate(f, st);
      // Finite differences of uv(st) give d(uv)/d(st); its inverse maps a step in u to a step in
      // st.
      const Vec2 du =
          (surface.evaluate(f, st + Vec2(h, 0)).uv - surface.evaluate(f, st - Vec2(h, 0)).uv) /
          (2 * h);
      const Vec2 dv =
          (surface.evaluate(f, st + Vec2(0, h)).uv - surface.evaluate(f, st - Vec2(0, h)).uv) /
          (2 * h);
      const glm::mat2 stOfUv = glm::inverse(glm::mat2(du, dv));
      for (int axis = 0; axis < 2; ++axis) {
        const Vec2 step = h * stOfUv[axis];
        const Vec3 fd =
            (surface.evaluate(f, st + step).P - surface.evaluate(f, st - step).P) / (2 * h);
        const Vec3 analytic = axis == 0 ? sp.Pu : sp.Pv;
        EXPECT_LT(glm::length(fd - analytic), 2e-3f * glm::length(analytic))
            << "face " << f << " axis " << axis;
      }
    }
}

TEST(LimitSurface, CollapsedUvFallsBackToPatchDerivatives) {
  ControlMesh mesh = test::grid(2);
  mesh.uvs = {Vec2(0.5f)};
  mesh.uvIndices.assign(mesh.faceVertices.size(), 0);
  const LimitSurface surface(mesh, SubdivisionScheme::CatmullClark);
  const LimitSurface plain(test::grid(2), SubdivisionScheme::CatmullClark);
  for (int f = 0; f < 4; ++f) {
    const SurfacePoint sp = surface.evaluate(f, Vec2(0.3f, 0.6f));
    ASSERT_TRUE(finitePoint(sp));
    EXPECT_EQ(sp.uv, Vec2(0.5f));
    EXPECT_LT(glm::length(sp.Pu - plain.evaluate(f, Vec2(0.3f, 0.6f)).Pu), 1e-6f);
  }
}

// Triangles and N-gons under Catmull-Clark have Bfr sub-faces; meso's st is a continuous chart.
TEST(LimitSurface, PolygonChartIsContinuousAndInterpolatesCorners) {
  for (int n : {3, 5, 6}) {
    ControlMesh mesh;
    for (int k = 0; k < n; ++k) {
      const float a = 2.0f * kPi * k / n;
      mesh.positions.emplace_back(std::cos(a), std::sin(a), 0.0f);
      mesh.faceVertices.push_back(k);
    }
    mesh.faceSizes = {n};
    const LimitSurface surface(mesh, SubdivisionScheme::CatmullClark);
    ASSERT_EQ(surface.faceSize(0), n);
    // Boundary corners of valence 2 are interpolated: some st of the chart reaches each corner.
    // Start at the nearest sample and refine by Gauss-Newton on |P(st) - corner|.
    const std::vector<Vec2> samples = domainSamples(40, false);
    for (int k = 0; k < n; ++k) {
      const Vec3 target = mesh.positions[k];
      Vec2 st = samples[0];
      for (Vec2 s : samples)
        if (glm::length(surface.evaluate(0, s).P - target) <
            glm::length(surface.evaluate(0, st).P - target))
          st = s;
      for (int iter = 0; iter < 30; ++iter) {
        const SurfacePoint sp = surface.evaluate(0, st);
        const glm::mat2 j(Vec2(sp.Pu), Vec2(sp.Pv));
        st += glm::inverse(j) * Vec2(target - sp.P);
      }
      EXPECT_LT(glm::length(surface.evaluate(0, st).P - target), 1e-5f) << n << "-gon corner " << k;
    }
    // Continuity: neighbouring samples give neighbouring points everywhere, seams included.
    const std::vector<Vec2> coarse = domainSamples(60, false);
    for (Vec2 st : coarse) {
      const SurfacePoint sp = surface.evaluate(0, st);
      ASSERT_TRUE(finitePoint(sp));
      EXPECT_NEAR(sp.P.z, 0.0f, 1e-6f);
      EXPECT_LT(glm::length(sp.N - Vec3(0.0f, 0.0f, 1.0f)), 1e-5f);
      for (Vec2 d : {Vec2(1e-3f, 0.0f), Vec2(0.0f, 1e-3f)}) {
        const SurfacePoint q = surface.evaluate(0, st + d);
        EXPECT_LT(glm::length(q.P - sp.P), 1e-2f) << n << "-gon at " << st.x << "," << st.y;
      }
    }
  }
}

// A flat triangle under the bilinear scheme is a similar image of its chart (the triangle's own
// shape at area one half): its sub-faces are the bilinear patches of the chart's kites in space,
// which the chart maps bilinearly too. So its surface point and tangents are exactly those of the
// affine map from the chart everywhere, across the sub-faces' seams, with orthogonal tangents of
// equal length (a relief on it is undistorted and isotropic, of one metric class); the same holds
// for Loop on a flat regular lattice; a degenerate triangle keeps the unit right triangle.
TEST(LimitSurface, BilinearTriangleIsASimilarImageOfItsChart) {
  ControlMesh mesh;
  mesh.positions = {Vec3(0.0f, 0.0f, 0.0f), Vec3(2.0f, 0.3f, 0.1f), Vec3(0.4f, 1.5f, -0.2f)};
  mesh.faceVertices = {0, 1, 2};
  mesh.faceSizes = {3};
  const LimitSurface surface(mesh, SubdivisionScheme::Bilinear);
  const Vec3 e0 = mesh.positions[1] - mesh.positions[0], e1 = mesh.positions[2] - mesh.positions[0];
  const Vec2 c0 = surface.cornerSt(0, 0), c1 = surface.cornerSt(0, 1), c2 = surface.cornerSt(0, 2);
  const glm::mat2 chart(c1 - c0, c2 - c0);
  EXPECT_NEAR(0.5f * std::abs(glm::determinant(chart)), 0.5f, 1e-5f);
  const glm::mat2 inv = glm::inverse(chart);
  // d P / d st: the columns of [e0 e1] chart^-1.
  const Vec3 pu = inv[0][0] * e0 + inv[0][1] * e1, pv = inv[1][0] * e0 + inv[1][1] * e1;
  EXPECT_NEAR(glm::dot(pu, pv), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::length(pu), glm::length(pv), 1e-5f);
  for (Vec2 l : domainSamples(24, true)) {
    const Vec2 st = c0 + l.x * (c1 - c0) + l.y * (c2 - c0);
    const SurfacePoint sp = surface.evaluate(0, st);
    EXPECT_LT(glm::length(sp.P - (mesh.positions[0] + l.x * e0 + l.y * e1)), 2e-6f)
        << l.x << "," << l.y;
    EXPECT_LT(glm::length(sp.Pu - pu), 2e-5f) << l.x << "," << l.y;
    EXPECT_LT(glm::length(sp.Pv - pv), 2e-5f) << l.x << "," << l.y;
    EXPECT_LT(glm::length(sp.uv - st), 2e-6f) << l.x << "," << l.y;
  }
  // Loop: on a flat regular lattice the limit surface is the lattice's affine map (linear
  // precision), so an inner face's chart is a similar image too.
  ControlMesh lattice;
  constexpr int kSide = 6;
  for (int j = 0; j <= kSide; ++j)
    for (int i = 0; i <= kSide; ++i)
      lattice.positions.emplace_back(1.3f * (i + 0.5f * j), 0.9f * j, 0.0f);
  for (int j = 0; j < kSide; ++j)
    for (int i = 0; i < kSide; ++i) {
      const int a = j * (kSide + 1) + i;
      test::addFace(lattice, {a, a + 1, a + kSide + 1});
      test::addFace(lattice, {a + 1, a + kSide + 2, a + kSide + 1});
    }
  const LimitSurface loop(lattice, SubdivisionScheme::Loop);
  const int inner = 2 * (3 * kSide + 3);
  const Vec2 centre =
      (loop.cornerSt(inner, 0) + loop.cornerSt(inner, 1) + loop.cornerSt(inner, 2)) / 3.0f;
  const SurfacePoint lp = loop.evaluate(inner, centre);
  EXPECT_NEAR(glm::dot(lp.Pu, lp.Pv), 0.0f, 1e-4f * glm::dot(lp.Pu, lp.Pu));
  EXPECT_NEAR(glm::length(lp.Pu), glm::length(lp.Pv), 1e-4f * glm::length(lp.Pu));
  mesh.positions[2] = Vec3(1.0f, 0.15f, 0.05f);  // on edge 0: no area
  const LimitSurface flat(mesh, SubdivisionScheme::Bilinear);
  EXPECT_EQ(flat.cornerSt(0, 1), Vec2(1.0f, 0.0f));
  EXPECT_EQ(flat.cornerSt(0, 2), Vec2(0.0f, 1.0f));
}

TEST(LimitSurface, CollapsedFacesGiveNoNan) {
  ControlMesh collapsed = test::grid(3);
  for (int v : {5, 6, 9, 10}) collapsed.positions[v] = Vec3(1.5f, 1.5f, 0.0f);  // the middle face
  ControlMesh point = test::grid(1);
  for (Vec3& p : point.positions) p = Vec3(0.25f);
  ControlMesh line = test::grid(2);
  for (Vec3& p : line.positions) p.y = 0.0f;
  for (const ControlMesh& mesh : {collapsed, point, line})
    for (SubdivisionScheme scheme :
         {SubdivisionScheme::CatmullClark, SubdivisionScheme::Bilinear}) {
      const LimitSurface surface(mesh, scheme);
      for (int f = 0; f < surface.numFaces(); ++f)
        for (Vec2 st : domainSamples(8, false)) {
          const SurfacePoint sp = surface.evaluate(f, st);
          ASSERT_TRUE(finitePoint(sp)) << "face " << f << " st " << st.x << "," << st.y;
        }
    }
}

// A bilinear quad with a collapsed edge (corners 2 and 3 coincide): dP/ds vanishes along t = 1,
// where the normal must still be finite and continue the normals nearby.
TEST(LimitSurface, DegenerateDerivativesUseTheNearbyNormal) {
  ControlMesh mesh;
  mesh.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0.8f), Vec3(0.5f, 1, 0), Vec3(0.5f, 1, 0)};
  test::addFace(mesh, {0, 1, 2, 3});
  const LimitSurface surface(mesh, SubdivisionScheme::Bilinear);
  for (float s : {0.0f, 0.3f, 0.5f, 1.0f}) {
    const SurfacePoint sp = surface.evaluate(0, Vec2(s, 1.0f));
    ASSERT_TRUE(finitePoint(sp));
    EXPECT_LT(glm::length(sp.Pu), 1e-6f);  // really degenerate here
    const Vec3 nearby = surface.evaluate(0, Vec2(s, 0.999f)).N;
    EXPECT_LT(glm::length(sp.N - nearby), 1e-2f) << "s " << s;
  }
}

TEST(LimitSurface, OutOfDomainCoordinatesAreClamped) {
  const LimitSurface surface(test::mixedPrism(), SubdivisionScheme::CatmullClark);
  for (int f = 0; f < surface.numFaces(); ++f)
    for (Vec2 st : {Vec2(-0.5f), Vec2(1.5f), Vec2(-1e-7f, 0.5f), Vec2(2.0f, -3.0f)}) {
      const SurfacePoint sp = surface.evaluate(f, st);
      ASSERT_TRUE(finitePoint(sp)) << "face " << f;
      EXPECT_LT(glm::length(sp.P), 2.0f);
    }
}

TEST(LimitSurface, IsMovable) {
  LimitSurface a(test::cube(), SubdivisionScheme::CatmullClark);
  const Vec3 p = a.evaluate(2, Vec2(0.3f, 0.4f)).P;
  LimitSurface b(std::move(a));
  EXPECT_EQ(b.evaluate(2, Vec2(0.3f, 0.4f)).P, p);
  LimitSurface c(test::grid(1), SubdivisionScheme::Bilinear);
  c = std::move(b);
  EXPECT_EQ(c.evaluate(2, Vec2(0.3f, 0.4f)).P, p);
}

// Heap bytes in use (the main arena and mappings of their own).
size_t heapInUse() {
  const struct mallinfo2 m = mallinfo2();
  return m.uordblks + m.hblkhd;
}

// memoryBytes, which --memory-limit counts before micropolygons are diced, against the heap that
// the surface holds once built: a grid (bilinear, with uv, as a ground is) and a Catmull-Clark
// torus (regular patches: one Bfr surface a chunk, 16 point indices a face). A bilinear quad keeps
// no Bfr surface, and OpenSubdiv's refiner (about 220 bytes a face) is released once the surfaces
// are made.
TEST(LimitSurface, MemoryBytesMatchTheHeapItHolds) {
  // Under AddressSanitizer (GCC's __SANITIZE_ADDRESS__ or clang's __has_feature, as
  // meso/core/huge_pages.h detects it) the heap is the sanitizer's, with its own bookkeeping.
  if (!kHugeNewBuilt) GTEST_SKIP() << "AddressSanitizer keeps its own heap";
  ControlMesh ground = test::grid(300);
  for (const Vec3& p : ground.positions) ground.uvs.emplace_back(p.x / 300.0f, p.y / 300.0f);
  ground.uvIndices = ground.faceVertices;
  const struct {
    const char* name;
    ControlMesh mesh;
    SubdivisionScheme scheme;
  } cases[] = {{"uv grid", ground, SubdivisionScheme::Bilinear},
               {"grid", test::grid(300), SubdivisionScheme::Bilinear},
               {"torus", test::torus(300, 100, 3.0f, 1.0f), SubdivisionScheme::CatmullClark}};
  for (const auto& c : cases) {
    const size_t before = heapInUse();
    const LimitSurface surface(c.mesh, c.scheme);
    const double held = double(heapInUse()) - double(before);
    const double estimate = double(surface.memoryBytes());
    std::printf("%s: %.1f MB held, %.1f MB estimated, %.1f bytes a face\n", c.name, held / 1e6,
                estimate / 1e6, estimate / c.mesh.numFaces());
    EXPECT_NEAR(estimate / held, 1.0, 0.1) << c.name;
    // The patch points of regular and bilinear faces are gathered from the mesh's points by index.
    // A plain bilinear quad reads its corners from the topology and keeps no polygon frame.
    if (c.mesh.hasUvs()) {  // its 2 Bfr surfaces would add 256 bytes a face, the refiner 220, its
      EXPECT_LT(held / c.mesh.numFaces(), 150.0);  // corner indices 16, a frame 24 (136 measured)
    }
    if (c.scheme == SubdivisionScheme::CatmullClark) {  // 16 patch points a face would add 128
      EXPECT_LT(held / c.mesh.numFaces(), 200.0);  // bytes, a Bfr surface a face 128 more (168)
    }
  }
}

}  // namespace
}  // namespace meso
