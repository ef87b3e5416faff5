// Schilling, "Antialiasing of Bump Maps": the slope (bump) pyramid and the roughness pyramid.
// Recursive rule: K_l = 1/4 sum K_{l-1,n} + 1/4 sum (f_n - f)(f_n - f)^T over the 2 x 2 children.
#pragma once

#include "meso/relief/height_table.h"
#include "meso/relief/slope_covariance.h"

#include <vector>

namespace meso {

// A filtered lookup: the mean slope (f_u, f_v) over the footprint and the covariance of the finest
// slopes around it that filtering removed (the extra roughness). Slopes are in the source's table
// units per unit of tile coordinate, like HeightSource::gradient().
struct SlopeSample {
  Vec2 mean{0.0f};
  SlopeCovariance roughness;
  float lod = 0.0f;  // the mip level used (0 = finest)

  // For a level with height amplitude * h(S u, S v): slopes per unit of u scale by k = amplitude *
  // S, covariances by k^2.
  SlopeSample scaled(float k) const { return {k * mean, (k * k) * roughness, lod}; }
};

// Level 0 holds the slope (offset-vector) map f = grad h at the texel centres of a W x H grid
// (powers of two) with zero roughness; level l + 1 holds the 2 x 2 box average of level l's slopes
// and the roughness factor (d1, d2, d3) of the recursive rule above, so that the covariance at a
// texel of level l equals the covariance of all level-0 slopes under it. Addressing wraps
// (periodic) or clamps. Immutable after construction; lookups are allocation-free and thread-safe.
class SlopePyramid {
 public:
  // Samples source.gradient() at the centres of a width x height grid. Throws meso::Error unless
  // both are powers of two.
  SlopePyramid(const HeightSource& source, int width, int height, bool periodic = true);
  // The table's own grid when its sides are powers of two (then level 0 is exactly the quadratic
  // derivative at the texel centres: central differences), else the next larger powers of two.
  explicit SlopePyramid(const HeightTable& table);

  int levels() const { return static_cast<int>(levels_.size()); }
  int width(int level = 0) const { return levels_[level].width; }
  int height(int level = 0) const { return levels_[level].height; }
  // Mean slope and roughness factor of texel (i, j) of a level (indices wrapped or clamped).
  Vec2 slope(int level, int i, int j) const;
  RoughnessFactor roughness(int level, int i, int j) const;

  // Trilinear lookup at tile coordinates p for a footprint given by its texel-space derivatives
  // dx = (du/dx W, dv/dx H), dy = (du/dy W, dv/dy H) (ray differentials times the level-0 size
  // width() x height(); for a level with tiling S include S). The mip level is
  // log2(max(|dx|, |dy|)), clamped to [0, levels() - 1]. Means are interpolated linearly, and so
  // are the texels' covariances K = D D^T (not D, which is not linear in K).
  SlopeSample lookup(Vec2 p, Vec2 dx, Vec2 dy) const;
  // The same at a given mip level (fractional: trilinear).
  SlopeSample lookupLevel(Vec2 p, float lod) const;

 private:
  struct Texel {
    float fu, fv;      // mean slope
    float d1, d2, d3;  // roughness factor
  };
  struct Level {
    int width, height;
    double inverseWidth, inverseHeight;
    std::vector<Texel> texels;
  };
  void build(const std::vector<Vec2>& finest, int width, int height);
  const Texel& texel(int level, int i, int j) const;
  void bilinear(int level, Vec2 p, Vec2& mean, SlopeCovariance& K) const;
  std::vector<Level> levels_;
  bool periodic_;
};

}  // namespace meso
