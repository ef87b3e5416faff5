// An Embree 3 scene of tessellated meshes and the closest-hit query the renderers use.
#pragma once

#include "meso/core/math.h"
#include "meso/geometry/tessellation.h"

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <vector>

namespace meso {

struct Ray {
  Vec3 origin{0.0f};
  Vec3 direction{0.0f, 0.0f, 1.0f};
  float tNear = 0.0f;
  float tFar = std::numeric_limits<float>::infinity();
};

struct RayHit {
  float t = 0.0f;
  int mesh = -1;      // index returned by RayScene::addMesh
  int triangle = -1;  // primitive index in that mesh; -1 in a grid not stored in it
  float b1 = 0.0f;    // Embree barycentrics (u, v) of corners 1 and 2
  float b2 = 0.0f;
  // A hit in a grid that knows its face (TriangleGrid::face): that face and the patch coordinates
  // of the hit, which the mesh's triangleFace and patchCoords would give (to float rounding)
  // without reading their per-triangle arrays, a cache miss each. -1: use the mesh.
  int face = -1;
  Vec2 st{0.0f};
  // Embree's geometric normal of the hit triangle (not normalized; its sign is Embree's winding,
  // so callers orient it themselves): it saves reading the triangle's corners back from memory.
  Vec3 Ng{0.0f};
};

// A block of a TessellatedMesh whose points and triangles form a regular grid, so that RayScene can
// store it as one Embree grid primitive (RTC_GEOMETRY_TYPE_GRID: about 8 times less acceleration
// memory than triangles and faster builds, shared/DESIGN.md section 5). Point (i, j), i < width,
// j < height, is positions[firstVertex + j * width + i]. Cell (i, j) is the two triangles
// firstTriangle + 2 (j (width - 1) + i) with corners (p(i, j), p(i+1, j), p(i, j+1)) and the next
// one with corners (p(i+1, j+1), p(i, j+1), p(i+1, j)): Embree's split of a grid cell.
struct TriangleGrid {
  // firstTriangle of a grid whose triangles are not stored in the mesh (TessellatedMesh::
  // gridOnlyTriangles): it must know its face, and hits in it report triangle -1.
  static constexpr uint32_t kNotInMesh = 0xFFFFFFFFu;
  uint32_t firstVertex = 0;
  uint32_t firstTriangle = 0;
  uint16_t width = 0;   // 2 .. 32767
  uint16_t height = 0;  // 2 .. 32767
  // Optional: the base face of every triangle of the grid and its patch coordinates, bilinear over
  // the grid: point (i, j) is at the bilinear blend of the corner points' st, cornerSt[0 .. 3] at
  // (0, 0), (width - 1, 0), (0, height - 1), (width - 1, height - 1), by i / (width - 1) and
  // j / (height - 1) (the tessellator checks this when it makes the grid). face -1: unknown (hits
  // then read the mesh's arrays).
  int32_t face = -1;
  std::array<Vec2, 4> cornerSt{};
  // The bilinear blend of cornerSt at grid point (i, j).
  Vec2 stAt(int i, int j) const {
    const float a = float(i) / float(width - 1), b = float(j) / float(height - 1);
    return (1.0f - b) * ((1.0f - a) * cornerSt[0] + a * cornerSt[1]) +
           b * ((1.0f - a) * cornerSt[2] + a * cornerSt[3]);
  }
};

class RayScene {
 public:
  RayScene();
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  // Adds a triangle mesh (the data is copied into Embree buffers) and returns its index. Throws
  // meso::Error for a mesh with triangles only grids hold.
  int addMesh(const TessellatedMesh& mesh);
  // The same, storing the listed grid blocks (disjoint, laid out as TriangleGrid says, e.g. from
  // tessellateAdaptive) as Embree grids and the other triangles as 2 x 2 grids, two to a grid
  // where consecutive ones share an edge (the stitching between rates). Hits report what
  // they would with addMesh(mesh): the mesh index, the mesh triangle of the cell that was hit and
  // barycentrics in it (triangle -1 in grids not stored in the mesh, whose face and st the hit
  // gives). Throws meso::Error on a grid that does not fit the mesh, or when the grids not stored
  // do not hold exactly the mesh's gridOnlyTriangles.
  int addMesh(const TessellatedMesh& mesh, const std::vector<TriangleGrid>& grids);
  // The same, with the mesh's points taken rather than copied (mesh.positions is left empty): with
  // grids, Embree reads them where they are, so a frame does not hold them twice. The points of the
  // triangles outside the grids go after them, in the room the vector's capacity leaves (4 points a
  // triangle, and one more), else in a larger array.
  int takeMesh(TessellatedMesh& mesh, const std::vector<TriangleGrid>& grids);
  // Builds the BVH. Must be called after the last addMesh and before intersect.
  void commit();
  // Closest hit along the ray; false on a miss. Thread-safe after commit().
  bool intersect(const Ray& ray, RayHit& hit) const;
  // True when anything lies on the ray between tNear and tFar (Embree's any-hit occlusion query,
  // cheaper than intersect: it stops at the first hit found). Thread-safe after commit().
  bool occluded(const Ray& ray) const;
  // The same queries for many rays at once, as one Embree ray stream. With `coherent` (rays of
  // one image tile, or shadow rays from neighbouring hits towards one light) Embree traces them in
  // packets: a default-scene frame's camera rays at 640x360 took 67 ms against 99 ms one by one
  // (tools/bench_frame trace_only); each ray's answer is Embree's for that ray (packet and
  // single-ray kernels may differ in rounding). found[i] / occluded[i] is 1 or 0. Thread-safe after
  // commit(); no allocation.
  void intersect(std::span<const Ray> rays, std::span<RayHit> hits, std::span<uint8_t> found,
                 bool coherent = true) const;
  void occluded(std::span<const Ray> rays, std::span<uint8_t> occluded, bool coherent = true) const;
  // Rays a stream call takes at most (its Embree rays live on the stack); longer spans are
  // traced in chunks of this many.
  static constexpr size_t kStreamChunk = 256;

  size_t numTriangles() const { return numTriangles_; }
  // Embree primitives: a triangle mesh's triangles, a grid geometry's grids and cells (a cell holds
  // one or two of the triangles outside the grids).
  size_t numPrimitives() const { return numPrimitives_; }
  // Bytes Embree holds for this scene (geometry buffers, BVH and build scratch) now, and the most
  // it has held at once so far, from Embree's device memory monitor.
  size_t deviceBytes() const;
  size_t peakDeviceBytes() const;
  // Bytes of the points the scene holds itself (takeMesh), which Embree reads in place.
  size_t heldBytes() const { return heldBytes_; }

 private:
  struct Impl;
  // The grid geometry of addMesh and takeMesh: Embree's own copy of the points, or `points` (the
  // mesh's, moved into the scene) when given.
  int addGrids(const TessellatedMesh& mesh, const std::vector<TriangleGrid>& grids,
               std::vector<Vec3>* points);
  std::unique_ptr<Impl> impl_;
  size_t numTriangles_ = 0;
  size_t numPrimitives_ = 0;
  size_t heldBytes_ = 0;
};

}  // namespace meso
