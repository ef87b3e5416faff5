// Small control meshes shared by the geometry tests.
#pragma once

#include "meso/geometry/control_mesh.h"

#include <cmath>
#include <initializer_list>

namespace meso::test {

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

}  // namespace meso::test
