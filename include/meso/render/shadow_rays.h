// Macro shadows (DESIGN.md section 6): one Embree occlusion ray per light from a hit on the frame's
// own geometry, the limit-surface tessellation or the displaced micropolygons.
#pragma once

#include "meso/geometry/ray_scene.h"
#include "meso/render/shading.h"
#include "meso/scene/scene.h"

namespace meso {

// Where a shadow ray starts: the hit on the traced triangles, lifted off them.
struct ShadowOrigin {
  Vec3 hit{0.0f};     // the primary ray's hit point on the traced triangle
  Vec3 facetN{0.0f};  // that triangle's unit normal (either orientation)
  Vec3 V{0.0f};       // unit direction towards the eye: the side the shadow ray leaves from
  float rayT = 0.0f;  // the primary ray's distance, which bounds the hit point's rounding error
  // The limit-surface point of the hit on undisplaced geometry (null on displaced micropolygons):
  // where the limit surface bulges above the chord (convex parts), the ray starts from its height,
  // so smooth normals near the terminator are not shadowed by the neighbouring facets.
  const Vec3* limitP = nullptr;
};

// The start point of shadow rays from o: on the viewer's side of the facet, lifted by
// shadowOffset(o) along its normal (and to the limit surface where that lies above the chord).
Vec3 shadowRayStart(const ShadowOrigin& o);
// The offset off the surface: a few thousand ulps of the hit's coordinates and distance, so that
// rounding of the hit point (which grows with both) never puts the start below the surface; about
// 3e-4 world units in the default scene, well under a micropolygon (about 5e-3 there).
float shadowOffset(const ShadowOrigin& o);

// The occlusion ray from `start` towards `light` (up to a point light's position); false when
// there is none to trace (a point light at the start itself, or a start inside a sphere light),
// and the light counts as visible. A point light with a radius is a sphere: the ray aims at a
// direction of the cone the sphere subtends, uniform in solid angle for xi uniform in [0, 1)^2,
// and stops short of the sphere (soft shadows, as the samples of a pixel average them).
bool shadowRay(const Light& light, const Vec3& start, Ray& ray, Vec2 xi = Vec2(0.5f));

// Two numbers in [0, 1) for the shadow ray of one camera sample (its film position, whose bits are
// unique per sample) and one light: the same whatever the thread count.
Vec2 shadowSample(Vec2 film, size_t light, uint64_t seed);

}  // namespace meso
