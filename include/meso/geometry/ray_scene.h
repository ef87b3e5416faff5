// An Embree 3 scene of tessellated meshes and the closest-hit query the renderers use.
#pragma once

#include "meso/core/math.h"
#include "meso/geometry/tessellation.h"

#include <limits>
#include <memory>
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
  int mesh = -1;       // index returned by RayScene::addMesh
  int triangle = -1;   // primitive index in that mesh
  float b1 = 0.0f;     // Embree barycentrics (u, v) of corners 1 and 2
  float b2 = 0.0f;
};

class RayScene {
 public:
  RayScene();
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  // Adds a triangle mesh (the data is copied into Embree buffers) and returns its index.
  int addMesh(const TessellatedMesh& mesh);
  // Builds the BVH. Must be called after the last addMesh and before intersect.
  void commit();
  // Closest hit along the ray; false on a miss. Thread-safe after commit().
  bool intersect(const Ray& ray, RayHit& hit) const;

  size_t numTriangles() const { return numTriangles_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  size_t numTriangles_ = 0;
};

}  // namespace meso
