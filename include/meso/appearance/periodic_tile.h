// A periodic tile of a displaced relief in Embree, and rays that wrap around it: the infinite
// periodic surface that the histograms and the consistency measurements look at.
#pragma once

#include "meso/appearance/histogram_builder.h"
#include "meso/geometry/ray_scene.h"

namespace meso {

class PeriodicTile {
 public:
  // Triangulates the height field over [0,1]^2 with n x n quads (edge vertices exactly on the
  // tile's sides) and builds its BVH.
  PeriodicTile(const PeriodicRelief& relief, int n);

  // Follows a ray from `origin` (inside the tile's x, y range) through the periodic copies of the
  // tile until it hits; on a hit returns true and the hit's coordinates wrapped into [0,1)^2.
  bool trace(Vec3 origin, const Vec3& direction, Vec2& hitXY) const;
  // The same, returning the hit point itself (x, y wrapped into [0,1)^2, z the traced mesh's).
  bool traceHit(Vec3 origin, const Vec3& direction, Vec3& hit) const;
  // A shadow ray: true when the ray from `origin` hits the periodic relief. A ray that rises above
  // zMax is free; one that crosses maxTiles tiles without doing so (the horizon) counts as blocked.
  bool occluded(Vec3 origin, const Vec3& direction, int maxTiles = 64) const;

  float zMin() const { return zMin_; }
  float zMax() const { return zMax_; }

 private:
  RayScene scene_;
  float zMin_ = 0.0f;
  float zMax_ = 0.0f;
};

}  // namespace meso
