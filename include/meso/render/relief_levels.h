// Relief levels at render time (DESIGN.md section 1): a material's height sources with amplitude,
// tiling scale and highest frequency, and their appearance tables.
#pragma once

#include "meso/appearance/level_tables.h"
#include "meso/relief/height_source.h"
#include "meso/relief/slope_pyramid.h"
#include "meso/render/synthesis_level.h"
#include "meso/scene/scene.h"

#include <memory>
#include <string>
#include <vector>

namespace meso {

// Level i of a material: height amplitude * h(S u, S v) in world units over the surface's (u, v).
struct ReliefLevel {
  std::unique_ptr<HeightSource> source;
  float amplitude = 0.0f;
  float scale = 1.0f;
  float freqPerU = 1.0f;  // highest frequency in cycles per unit of u
  // Schilling's slope and roughness pyramids, built only for the bump renderer (buildSlopePyramids).
  std::shared_ptr<const SlopePyramid> pyramid;

  // Shortest wavelength lambda_i = 1 / (freq_i S_i) in units of u (DESIGN.md section 3).
  float wavelength() const { return 1.0f / freqPerU; }
  float height(Vec2 uv) const { return amplitude * source->height(scale * uv); }
  // (B_u, B_v): derivatives of the world height with respect to u and v.
  Vec2 derivatives(Vec2 uv) const { return (amplitude * scale) * source->gradient(scale * uv); }
};

// Throws meso::Error naming the level's file and line for unreadable height images.
std::unique_ptr<HeightSource> makeHeightSource(const ReliefLevelDecl& decl);
ReliefLevel makeReliefLevel(const ReliefLevelDecl& decl);

// One period of a level as the table builders see it (histogram_builder.h): the tile is 1/S of u
// wide, scaled up by S, so heights are S * amplitude * h and slopes are the level's true slopes on
// a surface whose u has unit length.
class TileRelief : public PeriodicRelief {
 public:
  explicit TileRelief(const ReliefLevel& level) : level_(level) {}
  float height(float x, float y) const override {
    return level_.scale * level_.amplitude * level_.source->height({x, y});
  }
  Vec2 gradient(float x, float y) const override {
    return (level_.scale * level_.amplitude) * level_.source->gradient({x, y});
  }
  uint64_t fingerprint() const override;

 private:
  const ReliefLevel& level_;
};

// A level together with the tile view of it (keeps the level alive for the tile's lifetime).
std::unique_ptr<PeriodicRelief> makeTileRelief(const ReliefLevelDecl& decl);

// The levels of one material and their tables (tables[i] belongs to levels[i]; coarser tables are
// built over finer ones as in Figure 2).
struct MaterialRelief {
  std::vector<ReliefLevel> levels;
  std::vector<LevelTables> tables;
  // The level below the finest relief level (or the only one): fractal NDF synthesis, when the
  // material declares [materials.ndf].
  std::unique_ptr<SynthesisLevel> synthesis;
  int tablesBuilt = 0;
  int tablesFromCache = 0;
  double tablesSeconds = 0.0;
};

// The library's table settings for a scene's [render.tables].
TableSettings tableSettings(const TableResolution& resolution);

MaterialRelief buildMaterialRelief(const Material& material, const TableCache& cache,
                                   std::vector<std::string>* warnings, const TableSettings& settings = {});

// True when the material has anything for the relief renderers (levels or an NDF).
inline bool hasRelief(const Material& m) { return !m.relief.empty() || m.ndf.present; }

// Builds each level's slope pyramid: a height table's own texels (rounded up to powers of two), or
// a procedural source sampled 4 times per period of its highest frequency (at most 2048 x 2048).
void buildSlopePyramids(MaterialRelief& relief);

}  // namespace meso
