// Relief self-shadowing at render time (DESIGN.md section 6): the tabulated factor of a level
// (ShadowingTable) looked up per light, and the BRDF renderer with per-light shadowing.
#pragma once

#include "meso/appearance/brdf_table.h"
#include "meso/appearance/shadowing_table.h"
#include "meso/render/shading.h"
#include "meso/render/tile_map.h"
#include "meso/scene/scene.h"

#include <span>

namespace meso {

// Each light's self-shadowing factor of one level at a point whose tile map is `m` (as shadeBrdf
// takes it: area-preserving), seen from V: the tables of the two metric classes around the
// surface's own mixed by w (s1 may equal s0). Lights below the macro horizon get {1, 1} (they add
// nothing anyway); an empty table gives {1, 1}.
LightShadows reliefShadowing(std::span<const Light> lights, const Vec3& P, const TileMap& m,
                             const Vec3& V, const ShadowingTable& s0, const ShadowingTable& s1,
                             float w);

// shadeBrdf (level_shading.h, the TileMap overload) with each light's diffuse and specular terms
// scaled by `shadows`: the same lookups at the same angles, so {1, 1} for every light gives its
// value up to the order of float sums.
Vec3 shadeBrdfShadowed(const Material& material, std::span<const Light> lights, const Vec3& P,
                       const TileMap& m, const Vec3& V, const BrdfTable& t0, const BrdfTable& t1,
                       float w, const LightShadows& shadows);

}  // namespace meso
