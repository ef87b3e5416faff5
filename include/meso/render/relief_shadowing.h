// Relief self-shadowing at render time (DESIGN.md section 6): the tabulated factor of a level
// (ShadowingTable) looked up per light, and the BRDF renderer with per-light shadowing.
#pragma once

#include "meso/appearance/brdf_table.h"
#include "meso/appearance/shadowing_table.h"
#include "meso/render/displacement.h"
#include "meso/render/shading.h"
#include "meso/render/tile_map.h"
#include "meso/scene/scene.h"

#include <array>
#include <span>

namespace meso {

// The self-shadowing tables of a run of relief levels at one point, all looked up through one tile
// map: per level, the tables of the two metric classes around the surface's own (s1 may equal s0),
// mixed by w.
struct ShadowingLevels {
  std::array<const ShadowingTable*, kMaxReliefLevels> s0{}, s1{};
  size_t count = 0;
  float w = 0.0f;
  void add(const ShadowingTable& a, const ShadowingTable& b) {
    if (count < s0.size()) s0[count] = &a, s1[count++] = &b;
  }
  // Whether any level has a table: relief self-shadowing is on.
  bool any() const {
    for (size_t k = 0; k < count; ++k)
      if (!s0[k]->empty()) return true;
    return false;
  }
};

// Each light's self-shadowing factor of the levels at a point whose tile map is `m` (as shadeBrdf
// takes it: area-preserving), seen from V: the product over the levels, in their order. Lights
// below the mean plane get {1, 1}: on a flat surface every ray to them is blocked by the relief
// around, but on a convex one the peaks see past the smooth surface's horizon, which the macro
// shadow ray (blocked by the smooth surface) and the redistributed normals that face such a light
// stand for better than 0 would. An empty table gives {1, 1}. A
// light that `macro` (may be null) blocks entirely gets {1, 1} without lookups: its product with
// the macro shadow is 0 either way. The angles are computed once for all tables.
LightShadows reliefShadowing(std::span<const Light> lights, const Vec3& P, const TileMap& m,
                             const Vec3& V, const ShadowingLevels& levels,
                             const LightShadows* macro = nullptr);

// The BRDF renderer on a surface of any metric: V and each L go to tile coordinates by the
// area-preserving map `m` (makeTileMap with areaLengthPerU), the tables of the two metric classes
// around the surface's length per unit of u are looked up there and mixed by w (t1 may equal t0),
// and the diffuse term is scaled by |M^-1 L| so that a flat surface gets exactly L.N. Each light's
// diffuse and specular terms are scaled by `macro` times the self-shadowing of `levels` (macro
// first, then each level in order), looked up at the same angles; without shadows, all-lit macro
// shadows ({}) and no levels. Without self-shadowing, a light below the mean plane is looked up
// at theta_L > pi / 2 (the facets that face it); with it, such a light adds nothing. `firstLevel`
// (may be null) receives what reliefShadowing(lights, P, m, V, the first of `levels` alone, &macro)
// gives, from the same lookups.
Vec3 shadeBrdfShadowed(const Reflectance& material, std::span<const Light> lights, const Vec3& P,
                       const TileMap& m, const Vec3& V, const BrdfTable& t0, const BrdfTable& t1,
                       float w, const LightShadows& macro, const ShadowingLevels& levels,
                       LightShadows* firstLevel = nullptr);

}  // namespace meso
