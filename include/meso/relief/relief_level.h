// A relief level at render time (DESIGN.md section 1): a height source with amplitude, tiling scale
// and highest frequency over a surface's (u, v).
#pragma once

#include "meso/relief/height_source.h"
#include "meso/relief/slope_pyramid.h"

#include <memory>
#include <vector>

namespace meso {

// Level i of a material: height amplitude * h(S u, S v) in world units over the surface's (u, v).
struct ReliefLevel {
  std::unique_ptr<HeightSource> source;
  float amplitude = 0.0f;
  float scale = 1.0f;
  float freqPerU = 1.0f;  // highest frequency in cycles per unit of u
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

  // Shortest wavelength lambda_i = 1 / (freq_i S_i) in units of u (DESIGN.md section 3).
  float wavelength() const { return 1.0f / freqPerU; }
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
};

// 1024 fixed points of a level's (u, v), over 64 shortest wavelengths or one period of a height
// table: where the level's statistics (rms slope, height distribution) are sampled.
std::vector<Vec2> levelSamplePoints(const ReliefLevel& level);

// The mean square of the level's height derivative along u or along v (the larger), per unit of u,
// over levelSamplePoints: its squared rms slope on a unit-speed surface.
double levelSlopeMeanSquarePerU(const ReliefLevel& level);

}  // namespace meso
