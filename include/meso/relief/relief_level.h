// A relief level at render time (DESIGN.md section 1): a height source with amplitude, tiling scale
// and highest frequency over a surface's (u, v).
#pragma once

#include "meso/relief/height_source.h"
#include "meso/relief/slope_pyramid.h"
#include "meso/relief/solid_noise.h"

#include <memory>
#include <optional>
#include <vector>

namespace meso {

// Where a level is evaluated: the surface's (u, v) for relief over a parameterization; for solid
// relief also the point in solid space and that space's tangents per unit of u and of v, so that a
// step d in (u, v) is the step p + d.x pu + d.y pv in solid space (a local chart of the surface).
struct ReliefCoord {
  Vec2 uv{0.0f};
  Vec3 p{0.0f}, pu{0.0f}, pv{0.0f};
  ReliefCoord offset(Vec2 d) const { return {uv + d, p + d.x * pu + d.y * pv, pu, pv}; }
};

// Level i of a material: height amplitude * h(S u, S v) in world units over the surface's (u, v),
// or for a solid level amplitude * n(cells * p) at the surface's point p in solid space.
struct ReliefLevel {
  std::unique_ptr<HeightSource> source;
  float amplitude = 0.0f;
  float scale = 1.0f;
  float freqPerU = 1.0f;  // highest frequency in cycles per unit of u
  // Highest over lowest frequency of the source's octaves (HeightSource::lowestFrequency), >= 1:
  // 4 for three octaves of lacunarity 2, 1 for one octave or an image band.
  float octaveSpan = 1.0f;
  float midlevel = 0.0f;  // the table value that stays on the surface (default the source's mean)
  // Schilling's slope and roughness pyramids, built only for the bump renderer
  // (buildSlopePyramids).
  std::shared_ptr<const SlopePyramid> pyramid;
  // A band of a height image that finer levels continue (scene/relief_bands.h): this band and
  // every finer band of the image summed, the relief its tables describe, and one past the last
  // level that sum covers. Where this level is not raised whole, the renderers draw that sum as
  // one level (its bands are phase-aligned, so the finer bands' statistics are not independent of
  // this one's, as eq. (1) would assume). Null for every other level.
  std::shared_ptr<const ReliefLevel> partialSum;
  size_t partialSumEnd = 0;
  // A solid level (docs/solid-relief.md): the noise the renderers evaluate in solid space, with
  // solidCells lattice cells per unit of length there. `source` is then the periodic slice its
  // tables trace (SolidSlice), with scale = solidCells / its side, so every statistic made from
  // (u, v) (tables, visible heights, slopes) is the slice's on a unit-speed chart.
  std::shared_ptr<const SolidNoise> solid;
  float solidCells = 1.0f;

  // Shortest wavelength lambda_i = 1 / (freq_i S_i) in units of u (DESIGN.md section 3).
  float wavelength() const { return 1.0f / freqPerU; }
  // Longest wavelength whose octave carries the level's slopes, in units of u: where it spans
  // fewer than D pixels the level goes to its BRDF table (levelTransitions).
  float longestWavelength() const { return octaveSpan / freqPerU; }
  // World displacement amplitude * (h(S u, S v) - midlevel): centred, so the smooth surface that
  // bump, redistribution and BRDF draw is the relief's mean plane.
  float height(Vec2 uv) const { return amplitude * (source->height(scale * uv) - midlevel); }
  // (B_u, B_v): derivatives of the world height with respect to u and v.
  Vec2 derivatives(Vec2 uv) const { return (amplitude * scale) * source->gradient(scale * uv); }
  // height(uv), and derivatives(uv) in B, from one evaluation of the source (bit for bit the same).
  float heightAndDerivatives(Vec2 uv, Vec2& B) const {
    Vec2 g;
    const float h = source->heightAndGradient(scale * uv, g);
    B = (amplitude * scale) * g;
    return amplitude * (h - midlevel);
  }
  // The same at a surface point: solid levels evaluate their noise at c.p, with B the derivatives
  // along c.pu and c.pv (the 3-D gradient projected on the chart's tangents); the others at c.uv.
  float heightAndDerivatives(const ReliefCoord& c, Vec2& B) const {
    if (!solid) return heightAndDerivatives(c.uv, B);
    Vec3 g;
    const float h = solid->heightAndGradient(solidCells * c.p, g);
    B = (amplitude * solidCells) * Vec2(glm::dot(g, c.pu), glm::dot(g, c.pv));
    return amplitude * (h - midlevel);
  }
  // height(uv) at a surface point (solid levels at c.p): heightAndDerivatives' height, bit for bit.
  float height(const ReliefCoord& c) const {
    if (!solid) return height(c.uv);
    return amplitude * (solid->height(solidCells * c.p) - midlevel);
  }
  // d^2/dt^2 of the world height at c.offset(t w), t = 0 (w in units of u and v), where the source
  // has it in closed form; nullopt for solid levels and sources without it.
  std::optional<float> secondDerivative(const ReliefCoord& c, Vec2 w) const {
    if (solid) return std::nullopt;
    const std::optional<float> d2 = source->secondDerivative(scale * c.uv, scale * w);
    if (!d2) return std::nullopt;
    return amplitude * *d2;
  }
  Vec2 derivatives(const ReliefCoord& c) const {
    if (!solid) return derivatives(c.uv);
    Vec2 B;
    heightAndDerivatives(c, B);
    return B;
  }
};

// 1024 fixed points of a level's (u, v), over 64 shortest wavelengths or one period of a height
// table: where the level's statistics (rms slope, height distribution) are sampled.
std::vector<Vec2> levelSamplePoints(const ReliefLevel& level);

// Quads per tile side at which the tables trace a level's tile (PeriodicTile): `base`
// (render.tables.mesh_resolution) for a source defined everywhere; for a sampled one (a height
// image) enough to resolve its interpolated surface where the level has energy, 8 quads per cycle
// of its highest frequency up to two per texel (every texel centre a vertex, each texel's bilinear
// patch split 2 x 2), never below base and at most kMaxTableMeshResolution.
inline constexpr int kMaxTableMeshResolution = 1024;
int tableMeshResolution(const ReliefLevel& level, int base);

// The mean square of the level's height derivative along u or along v (the larger), per unit of u,
// over levelSamplePoints: its squared rms slope on a unit-speed surface.
double levelSlopeMeanSquarePerU(const ReliefLevel& level);

}  // namespace meso
