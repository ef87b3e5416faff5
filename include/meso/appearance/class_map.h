// The affine map between two metric classes of one relief level (docs/metric.md): an affine map of
// (x, y, height) space keeps orthographic projection and occlusion, so a class's visible normals
// and shadows are another tile's seen through the map.
#pragma once

#include "meso/appearance/histogram_builder.h"
#include "meso/core/math.h"

namespace meso {

// M = [[a, b, 0], [0, 1 / a, 0], [0, 0, t]] takes a tile's (x, y, height) to a class's frame: the
// class's area-preserving shape on the tangents and t the ratio of the tile's lengths per unit of
// u to the class's (tile heights go as 1 / length). t = 1 is the tracing of one class through its
// own shape (histogram_builder.cpp).
struct ClassMap {
  MetricShape shape;
  float t = 1.0f;

  bool identity() const { return shape.identity() && t == 1.0f; }
  // A direction of the class's frame in the tile's: normalize(M^-1 w). Views and lights.
  Vec3 toTile(const Vec3& w) const {
    return glm::normalize(Vec3(w.x / shape.a - shape.b * w.y, shape.a * w.y, w.z / t));
  }
  // A tile normal in the class's frame: normalize(M^-T n).
  Vec3 normalFromTile(const Vec3& n) const {
    return glm::normalize(Vec3(n.x / shape.a, shape.a * n.y - shape.b * n.x, n.z / t));
  }
  // The horizontal part of M^-1 (unnormalized): every direction of one azimuth about the class's
  // normal shares its horizontal tile direction.
  Vec2 horizontalToTile(Vec2 w) const { return {w.x / shape.a - shape.b * w.y, shape.a * w.y}; }
};

}  // namespace meso
