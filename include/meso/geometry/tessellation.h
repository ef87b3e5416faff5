// Triangles of a limit surface (OpenSubdiv Bfr::Tessellation) that remember their patch
// coordinates.
#pragma once

#include "meso/core/math.h"
#include "meso/geometry/limit_surface.h"

#include <cstdint>
#include <vector>

namespace meso {

// Triangles over the limit surface. Vertices on edges shared by two faces are evaluated once and
// shared, so the mesh is watertight. Each triangle keeps its base face and the patch coordinates of
// its three corners, so a hit's barycentrics give the patch coordinates to evaluate the limit
// there.
struct TessellatedMesh {
  std::vector<Vec3> positions;
  std::vector<uint32_t> indices;  // 3 per triangle
  std::vector<int> triangleFace;  // base face of each triangle
  std::vector<Vec2> cornerSt;     // 3 per triangle: patch coordinates of its corners in that face
  // Triangles that only the tessellation's grids hold (TriangleGrid::kNotInMesh, tessellated with
  // DicingSettings::gridsOnly): they have points above but no entries in the per-triangle arrays.
  size_t gridOnlyTriangles = 0;

  // Triangles stored in the arrays above.
  size_t numTriangles() const { return triangleFace.size(); }
  // Every triangle: those stored and those only grids hold.
  size_t numMicropolygons() const { return numTriangles() + gridOnlyTriangles; }
  // Patch coordinates inside triangle `tri` at Embree barycentrics (b1, b2) of corners 1 and 2.
  Vec2 patchCoords(size_t tri, float b1, float b2) const {
    const Vec2* c = &cornerSt[3 * tri];
    return (1.0f - b1 - b2) * c[0] + b1 * c[1] + b2 * c[2];
  }
};

// Tessellates every face that has a limit surface with `rate` segments per edge (rate >= 1).
TessellatedMesh tessellateUniform(const LimitSurface& surface, int rate);

}  // namespace meso
