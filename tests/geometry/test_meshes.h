// Small control meshes, a relief and a mesh check shared by the geometry tests.
#pragma once

#include "meso/core/rng.h"
#include "meso/geometry/adaptive_tessellation.h"
#include "meso/geometry/control_mesh.h"
#include "meso/geometry/tessellation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <map>
#include <tuple>
#include <utility>
#include <vector>

namespace meso::test {

// A direction uniform on the unit sphere.
inline Vec3 randomDirection(Rng& rng) {
  const float z = 1.0f - 2.0f * rng.uniform(), phi = 2.0f * kPi * rng.uniform();
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

inline void addFace(ControlMesh& mesh, std::initializer_list<int> vertices) {
  mesh.faceSizes.push_back(static_cast<int>(vertices.size()));
  mesh.faceVertices.insert(mesh.faceVertices.end(), vertices);
}

// The cube [-1, 1]^3 as 6 quads, counter-clockwise seen from outside.
inline ControlMesh cube() {
  ControlMesh mesh;
  for (int i = 0; i < 8; ++i)
    mesh.positions.emplace_back(i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f);
  addFace(mesh, {0, 2, 3, 1});  // z = -1
  addFace(mesh, {4, 5, 7, 6});  // z = +1
  addFace(mesh, {0, 1, 5, 4});  // y = -1
  addFace(mesh, {2, 6, 7, 3});  // y = +1
  addFace(mesh, {0, 4, 6, 2});  // x = -1
  addFace(mesh, {1, 3, 7, 5});  // x = +1
  return mesh;
}

// An n x n grid of unit quads in the plane z = 0, from (0, 0) to (n, n), facing +z.
inline ControlMesh grid(int n) {
  ControlMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) mesh.positions.emplace_back(i, j, 0.0f);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      addFace(mesh, {a, a + 1, a + n + 2, a + n + 1});
    }
  return mesh;
}

// A torus around the z axis: n quads around the ring (radius R), m around the tube (radius r),
// counter-clockwise seen from outside; face j * n + i spans ring step i and tube step j, and tube
// step 0 starts at the outer equator.
inline ControlMesh torus(int n, int m, float R, float r) {
  ControlMesh mesh;
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i) {
      const float theta = 6.2831853f * static_cast<float>(i) / static_cast<float>(n);
      const float phi = 6.2831853f * static_cast<float>(j) / static_cast<float>(m);
      mesh.positions.emplace_back((R + r * std::cos(phi)) * std::cos(theta),
                                  (R + r * std::cos(phi)) * std::sin(theta), r * std::sin(phi));
    }
  const auto at = [&](int i, int j) { return ((j + m) % m) * n + (i + n) % n; };
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i)
      addFace(mesh, {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
  return mesh;
}

// A closed pentagonal prism around the origin whose sides are quads except one split into two
// triangles: quads, triangles and pentagons in one closed surface.
inline ControlMesh mixedPrism() {
  ControlMesh mesh;
  for (int z = 0; z < 2; ++z)
    for (int k = 0; k < 5; ++k) {
      const float a = 2.0f * kPi * k / 5.0f;
      mesh.positions.emplace_back(1.5f * std::cos(a), 1.5f * std::sin(a), z ? 1.0f : -1.0f);
    }
  addFace(mesh, {4, 3, 2, 1, 0});  // bottom, facing -z
  addFace(mesh, {5, 6, 7, 8, 9});  // top, facing +z
  addFace(mesh, {0, 1, 6});        // side 0 split into two triangles
  addFace(mesh, {0, 6, 5});
  for (int k = 1; k < 5; ++k) addFace(mesh, {k, (k + 1) % 5, (k + 1) % 5 + 5, k + 5});
  return mesh;
}

// The cube [-1, 1]^3 with n x n quads on each side, counter-clockwise seen from outside: many
// faces, so near and far faces sit side by side.
inline ControlMesh refinedCube(int n) {
  ControlMesh mesh;
  std::map<std::tuple<int, int, int>, int> index;
  auto vertex = [&](int i, int j, int k) {
    const auto [it, added] = index.try_emplace({i, j, k}, static_cast<int>(mesh.positions.size()));
    if (added) mesh.positions.push_back(Vec3(i, j, k) * (2.0f / n) - Vec3(1.0f));
    return it->second;
  };
  // Each side: a fixed axis at 0 or n, and two running axes (a, b) with a x b pointing outward.
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int a = (axis + (side ? 1 : 2)) % 3, b = (axis + (side ? 2 : 1)) % 3;
      for (int p = 0; p < n; ++p)
        for (int q = 0; q < n; ++q) {
          int c[4][3];
          const int corners[4][2] = {{p, q}, {p + 1, q}, {p + 1, q + 1}, {p, q + 1}};
          for (int k = 0; k < 4; ++k) {
            c[k][axis] = side * n;
            c[k][a] = corners[k][0];
            c[k][b] = corners[k][1];
          }
          addFace(mesh, {vertex(c[0][0], c[0][1], c[0][2]), vertex(c[1][0], c[1][1], c[1][2]),
                         vertex(c[2][0], c[2][1], c[2][2]), vertex(c[3][0], c[3][1], c[3][2])});
        }
    }
  return mesh;
}

// A smooth relief of both signs along the limit normal: 0.05 sin sin sin of the limit position,
// continuous across faces because P and N are.
struct WaveDisplacement : VertexDisplacement {
  float amplitude = 0.05f;
  Vec3 offset(int, Vec2, const SurfacePoint& sp) const override {
    const Vec3 p = sp.P;
    return amplitude * std::sin(5.0f * p.x) * std::sin(4.0f * p.y + 1.0f) *
           std::sin(3.0f * p.z + 2.0f) * sp.N;
  }
  float bound() const override { return amplitude; }
};

// Every edge used by exactly two triangles, once in each direction: closed and oriented.
inline int countOpenEdges(const TessellatedMesh& mesh) {
  std::map<std::pair<uint32_t, uint32_t>, int> uses;  // +1 forward, +16 backward
  for (size_t t = 0; t < mesh.numTriangles(); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = mesh.indices[3 * t + k], b = mesh.indices[3 * t + (k + 1) % 3];
      uses[{std::min(a, b), std::max(a, b)}] += a < b ? 1 : 16;
    }
  int open = 0;
  for (const auto& [edge, count] : uses) open += count != 17;
  return open;
}

// The legs (two shorter edges: a grid cell's sides) of the triangles wholly in view, in pixel
// footprints: their 99th percentile and largest.
struct InViewLegs {
  float p99 = 0.0f, worst = 0.0f;
};
inline InViewLegs inViewLegs(const TessellatedMesh& m, const ScreenMetric& screen) {
  std::vector<float> legs;
  for (size_t k = 0; k < m.numTriangles(); ++k) {
    const Vec3 p[3] = {m.positions[m.indices[3 * k]], m.positions[m.indices[3 * k + 1]],
                       m.positions[m.indices[3 * k + 2]]};
    if (!screen.pointInView(p[0]) || !screen.pointInView(p[1]) || !screen.pointInView(p[2]))
      continue;
    float e[3];
    for (int i = 0; i < 3; ++i) e[i] = screen.footprintLength(p[i], p[(i + 1) % 3]);
    std::sort(e, e + 3);
    legs.push_back(e[1]);
  }
  std::sort(legs.begin(), legs.end());
  if (legs.empty()) return {};
  return {legs[legs.size() * 99 / 100], legs.back()};
}

}  // namespace meso::test
