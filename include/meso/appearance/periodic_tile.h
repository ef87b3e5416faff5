// A periodic tile of a displaced relief in Embree, and rays that wrap around it: the infinite
// periodic surface that the histograms and the consistency measurements look at.
#pragma once

#include "meso/appearance/histogram_builder.h"
#include "meso/geometry/ray_scene.h"

#include <span>
#include <vector>

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

  // The horizon of the traced surface seen from `origin` towards the unit horizontal tile direction
  // u, as far as the light slopes `slopes` (tan of each light's elevation in tile coordinates,
  // ascending) need it: for each slope e there, occluded(origin, normalize(Vec3(u, e)), maxTiles)
  // is false exactly when e > the result (up to float rounding at e = the horizon). The relief is
  // a height field, so one march over the same triangles as the tracer, with early termination,
  // stands for a shadow ray per slope.
  float horizon(const Vec3& origin, Vec2 u, std::span<const float> slopes, int maxTiles) const;

  float zMin() const { return zMin_; }
  float zMax() const { return zMax_; }

 private:
  float cellHeight(int i, int j, double fx, double fy) const;

  RayScene scene_;
  int n_ = 0;                   // quads per tile side
  std::vector<float> heights_;  // (n + 1)^2 vertex heights, row-major in y
  // maxLevels_[l]: the highest vertex of each block of 2^l x 2^l quads, ceil(n / 2^l) blocks a
  // side (l = 0: the quads), up to one block for the tile.
  std::vector<std::vector<float>> maxLevels_;
  float zMin_ = 0.0f;
  float zMax_ = 0.0f;
};

}  // namespace meso
