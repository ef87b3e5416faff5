// A pinhole view as dicing and view tests see it: pixel lengths, footprints and frustum tests of
// points, segments and boxes.
#pragma once

#include "meso/core/math.h"

#include <array>

namespace meso {

// A pinhole view reduced to what dicing needs, independent of the scene area. The frame and pixel
// conventions are those of meso::Camera: pixel (0, 0) is the top-left corner, x grows along
// `right`, y against `up`, and the vertical field of view spans `height` pixels.
struct ScreenMetric {
  Vec3 eye{0.0f, 0.0f, 5.0f};
  Vec3 forward{0.0f, 0.0f, -1.0f};  // forward, right, up: orthonormal
  Vec3 right{1.0f, 0.0f, 0.0f};
  Vec3 up{0.0f, 1.0f, 0.0f};
  float tanHalfFovY = 0.36397023f;  // tan(20 degrees)
  int width = 640;
  int height = 360;
  // Points nearer than this (along `forward`) count as behind the eye: segments are clipped there,
  // which bounds the pixel length of geometry that touches the eye.
  float nearDistance = 1e-3f;

  // The frame meso::Camera builds from these settings.
  static ScreenMetric lookAt(Vec3 eye, Vec3 target, Vec3 up, float fovYDegrees, int width,
                             int height);

  float depth(Vec3 p) const { return glm::dot(p - eye, forward); }
  // Pixels that one world unit spans at this depth, perpendicular to the view direction.
  float pixelsPerUnit(float depth) const;
  // Pixel position of a point in front of the eye (depth >= nearDistance); points off screen get
  // positions outside [0, width] x [0, height] by the same perspective map.
  Vec2 toPixels(Vec3 p) const;
  // Length in pixels of the image of segment ab. The part behind the near plane is clipped away
  // (0 when all of it is); parts off screen are measured by the same projection, so a segment that
  // crosses the image border gets the point density its visible part needs.
  float projectedLength(Vec3 a, Vec3 b) const;
  // Pixels per world unit at p in the direction the perspective map stretches most: the largest
  // singular value of its Jacobian, pixelsPerUnit(depth) * distance / depth (the pixel footprint
  // shrinks off axis), the ratio clamped to the image corner's. No segment near a point p in view
  // projects longer than this many pixels per unit.
  float pixelDensity(Vec3 p) const;
  // Length of segment ab in pixel footprints: its world length times pixelDensity, averaged along
  // it (Simpson's rule), and never less than projectedLength. Unlike projectedLength it does not
  // shrink where the segment runs along the view direction, which is what grazing views need
  // (Cycles' DiagSplit measures edges by world length over the pixel footprint too). Clipped at
  // the near plane like projectedLength.
  float footprintLength(Vec3 a, Vec3 b) const;
  // p lies in front of the near plane and projects into [0, width] x [0, height].
  bool pointInView(Vec3 p) const;
  // False when the box [lo - grow, hi + grow] lies wholly outside the view frustum (beyond one of
  // its four side planes or behind the near plane); conservative: true when unsure.
  bool boxInView(Vec3 lo, Vec3 hi, float grow) const;
  // False when every point within `distance` of the box [lo, hi] lies outside the view frustum:
  // the box grown by a ball, not a cube, so tighter than boxInView(lo, hi, distance) beside the
  // frustum's slanted planes. Conservative.
  bool boxNearView(Vec3 lo, Vec3 hi, float distance) const;
  // The view frustum as the half-spaces dot(n, p - eye) <= c (left, right, top, bottom, near),
  // n not normalized.
  struct Plane {
    Vec3 n;
    float c;
  };
  std::array<Plane, 5> viewPlanes() const;
};

}  // namespace meso
