// Shading of one hit on an object: picks the renderer of each relief level by its transition
// parameter (DESIGN.md sections 2 and 3) and returns the AOVs the film records.
#pragma once

#include "meso/render/render_context.h"
#include "meso/render/shading.h"
#include "meso/render/tile_map.h"

#include <array>
#include <span>

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

// A sample's footprint on the surface from ray differentials: how (u, v) change per pixel step of
// the sample's film position in x and in y (scaled down by sqrt(spp), since a pixel averages its
// samples). Only the bump renderer uses it, to filter its lookups (Schilling's pyramids).
struct Footprint {
  Vec2 dUVdx{0.0f};
  Vec2 dUVdy{0.0f};
  bool valid = false;
};

// The footprint of a hit at P with surface frame (Pu, Pv, N): the neighbouring rays rx, ry meet the
// tangent plane at P + dP/dx, P + dP/dy, and dP = Pu du + Pv dv is solved by least squares. Invalid
// (and harmless) when a neighbouring ray misses the plane or the frame is degenerate.
Footprint footprintAt(const SurfacePoint& sp, const Ray& rx, const Ray& ry, float scale);

// The map through which a level's BRDF and self-shadowing tables are looked up on a frame (P_u,
// P_v, N) at metric position `metric`: the frame's tangents as class k0's shape sees them, at the
// frame's own length clamped to the two classes' (tableLengthPerU).
TileMap tableTileMap(const MaterialRelief& relief, const MetricPosition& metric, const Vec3& Pu,
                     const Vec3& Pv, const Vec3& N);

struct ShadeResult {
  Vec3 colour{0.0f};
  Vec3 algorithm{0.0f};
  Vec3 normal{0.0f, 0.0f, 1.0f};               // the shading normal, facing the eye
  float T = 0.0f;                              // of the finest visible level; 0 without relief
  float synthesis = 0.0f;                      // how much synthesized detail shows (0 none, 1 full)
  std::array<float, kMaxReliefLevels> disp{};  // per level, the disp shading assumed (auto mode)
};

// sp is the limit surface at the hit's patch coordinates (never the facet), with P the hit point
// itself on displaced geometry; V the unit direction to the eye; `lights` the sample's lights (the
// scene's, then its environment's samples: RenderContext::lightsPerSample), indexed as `shadows`.
// T's terminator term takes the scene's own lights only (docs/environment.md). facetNormal (the hit
// triangle's unit normal) is used instead of the Blinn normal when the context asks for facet
// normals and the object is displaced by --algorithm displacement; it may be null otherwise.
// footprint (may be null) filters the bump renderer's slope lookups and widens its highlight by
// the roughness filtering removed. limitP (may be null: sp.P) is the limit-surface point of the
// hit, from which T and disp are evaluated as the tessellator did. shadows (may be null: no
// shadows at all, the unshadowed images bit for bit) is each light's macro visibility at the hit;
// the relief's tabulated self-shadowing multiplies it where a level is not displaced.
// reflectance (may be null: the material's constants) is what the colour textures give at the hit
// (textureReflectance). lengthPerU (0: the hit's own max(|P_u|, |P_v|)) is the object's UvSpeed
// at the hit, which T reads as the tessellator's ReliefDisplacement does.
ShadeResult shadeSurface(const RenderContext& ctx, const PreparedObject& object,
                         const SurfacePoint& sp, const Vec3& V, std::span<const Light> lights,
                         const Vec3* facetNormal = nullptr, const Footprint* footprint = nullptr,
                         const Vec3* limitP = nullptr, const LightShadows* shadows = nullptr,
                         const Reflectance* reflectance = nullptr, float lengthPerU = 0.0f);

// The material's reflectance with its colour textures (kd, ks images) looked up at uv, filtered
// over the footprint (a point lookup where it is not valid). Textures and relief share (u, v):
// kd and ks scale the tables' diffuse and specular parts, which assumes the colour uncorrelated
// with the relief below a pixel.
Reflectance textureReflectance(const RenderContext& ctx, int material, Vec2 uv,
                               const Footprint& footprint);

}  // namespace meso
