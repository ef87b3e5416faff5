// Shading of one hit on an object: picks the renderer of each relief level by its transition
// parameter (DESIGN.md sections 2 and 3) and returns the AOVs the film records.
#pragma once

#include "meso/render/render_context.h"

namespace meso {

// The colours of the algorithm layer (DESIGN.md section 2).
namespace algorithm_colour {
inline constexpr Vec3 kBrdf{1.0f, 1.0f, 0.0f};
inline constexpr Vec3 kBump{0.0f, 1.0f, 0.0f};
inline constexpr Vec3 kRedistribution{0.0f, 0.0f, 1.0f};
inline constexpr Vec3 kDisplacement{1.0f, 0.0f, 0.0f};
inline constexpr Vec3 kSynthesis{1.0f, 0.0f, 1.0f};
inline constexpr Vec3 kSmooth{0.5f, 0.5f, 0.5f};  // a material without relief
}  // namespace algorithm_colour

struct ShadeResult {
  Vec3 colour{0.0f};
  Vec3 algorithm{0.0f};
  Vec3 normal{0.0f, 0.0f, 1.0f};  // the shading normal, facing the eye
  float T = 0.0f;                 // of the finest visible level; 0 without relief
};

// sp is the limit surface at the hit's patch coordinates (never the facet), with P the hit point
// itself on displaced geometry; V the unit direction to the eye. facetNormal (the hit triangle's
// unit normal) is used instead of the Blinn normal when the context asks for facet normals and the
// object is displaced by --algorithm displacement; it may be null otherwise.
ShadeResult shadeSurface(const RenderContext& ctx, const PreparedObject& object, const SurfacePoint& sp,
                         const Vec3& V, const Vec3* facetNormal = nullptr);

}  // namespace meso
