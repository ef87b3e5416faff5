// Relief levels at render time (DESIGN.md section 1): a material's height sources with amplitude,
// tiling scale and highest frequency, and their appearance tables.
#pragma once

#include "meso/appearance/level_tables.h"
#include "meso/relief/height_source.h"
#include "meso/relief/slope_pyramid.h"
#include "meso/render/synthesis_level.h"
#include "meso/render/visible_height.h"
#include "meso/scene/scene.h"

#include <memory>
#include <span>
#include <string>
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

// Throws meso::Error naming the level's file and line for unreadable height images.
std::unique_ptr<HeightSource> makeHeightSource(const ReliefLevelDecl& decl);
ReliefLevel makeReliefLevel(const ReliefLevelDecl& decl);
// Sets partialSum and partialSumEnd of every band of a height image that finer bands of the same
// image continue (levels[i] made from decls[i]).
void linkImageBands(std::span<const ReliefLevelDecl> decls, std::vector<ReliefLevel>& levels);

// One period of a level as the table builders see it (histogram_builder.h), on a surface whose
// unit of u and of v is `lengthPerU` world units long (an isotropic metric, docs/metric.md): the
// tile is 1/S of u wide, that is lengthPerU / S world units, so in tile units heights are
// S * amplitude * h / lengthPerU and slopes are the level's true world slopes.
class TileRelief : public PeriodicRelief {
 public:
  explicit TileRelief(const ReliefLevel& level, float lengthPerU = 1.0f)
      : level_(level),
        factor_(level.scale * level.amplitude / lengthPerU),
        lengthPerU_(lengthPerU) {}
  float height(float x, float y) const override { return factor_ * level_.source->height({x, y}); }
  Vec2 gradient(float x, float y) const override {
    return factor_ * level_.source->gradient({x, y});
  }
  uint64_t fingerprint() const override;

 private:
  const ReliefLevel& level_;
  float factor_;
  float lengthPerU_;
};

// A level together with the tile view of it (keeps the level alive for the tile's lifetime).
std::unique_ptr<PeriodicRelief> makeTileRelief(const ReliefLevelDecl& decl);

// The tables of every level for one isotropic metric class (docs/metric.md): the relief as seen on
// a surface whose unit of u is lengthPerU world units long.
struct MetricTables {
  float lengthPerU = 1.0f;
  MetricShape shape;                // the area-preserving stretch and shear of the class
  std::vector<LevelTables> levels;  // levels[i] belongs to MaterialRelief::levels[i]
};

// A metric class to build: isotropic length and shape.
struct MetricClass {
  float lengthPerU = 1.0f;
  MetricShape shape;
};

// The shape and length of a frame: [P_u, P_v] in the orthonormal frame (P_u / |P_u|, N x that) is
// l [[a, b], [0, 1 / a]] with l = sqrt |P_u x P_v|.
MetricClass metricOf(const Vec3& Pu, const Vec3& Pv);

// Where a surface's own metric falls between the classes: the classes of the nearest shape (in
// log a and b) whose lengths bracket the surface's, k0 and k1 (equal at the ends), mixed by w in
// log length; `nearest` is the closer one.
struct MetricPosition {
  int k0 = 0, k1 = 0, nearest = 0;
  float w = 0.0f;
};

// The levels of one material and their tables (coarser tables are built over finer ones as in
// Figure 2), one set per metric class the scene needs.
struct MaterialRelief {
  std::vector<ReliefLevel> levels;
  std::vector<MetricTables> metrics;  // sorted by lengthPerU; one class when the metric is constant
  // None when the renderer reads no tables (TableSettings::build false: bump and displacement).
  const LevelTables& tables(size_t level, int metric = 0) const {
    return metrics[metric].levels[level];
  }
  MetricPosition metricAt(const MetricClass& m) const;
  // metricAt(metricOf(Pu, Pv)), without measuring the metric when there is one class or none
  // (class 0, w 0 either way): the shader asks this for every sample.
  MetricPosition metricAt(const Vec3& Pu, const Vec3& Pv) const {
    return metrics.size() > 1 ? metricAt(metricOf(Pu, Pv)) : MetricPosition{};
  }
  // The level below the finest relief level (or the only one): fractal NDF synthesis, when the
  // material declares [materials.ndf].
  std::unique_ptr<SynthesisLevel> synthesis;
  // Per level, where the hybrid draws it flat (visible_height.h); built once per render context
  // (buildVisibleHeights), empty for the other renderers.
  std::vector<VisibleHeight> visibleHeights;
  int tablesBuilt = 0;
  int tablesFromCache = 0;
  double tablesSeconds = 0.0;
};

// Fills relief.visibleHeights, one per level. Levels after the first ride on the crests of raised
// coarser ones and get crest tables; the first does when its surfaces are curved (it rides on the
// limit surface's own crests), and skips the march on planes.
void buildVisibleHeights(MaterialRelief& relief, bool curvedSurface);

// The library's table settings for a scene's [render.tables].
TableSettings tableSettings(const TableResolution& resolution);

// Builds (or loads) the tables of every level for each metric class (sorted by shape, then length,
// here). Empty means the unit metric only.
MaterialRelief buildMaterialRelief(const Material& material, const TableCache& cache,
                                   std::vector<std::string>* warnings,
                                   const TableSettings& settings = {},
                                   std::vector<MetricClass> classes = {});

// At most this many metric classes per material (each is a table set per level, about 11 MB and
// half a second to a few seconds to build; a UV sphere needs 15, a torus 6): a surface whose
// metric is garbage, such as a mesh so far from the origin that its float positions collapse, once
// asked for 111 classes (332 table sets, minutes to build and gigabytes to hold).
inline constexpr size_t kMaxMetricClasses = 32;
// The stretch a and shear b of a class are clamped to [1/16, 16] (a 256:1 ratio of |P_u| to
// |P_v|) and [-4, 4]; a sample beyond is looked up in the nearest class (docs/metric.md).
inline constexpr float kMaxMetricStretch = 16.0f;
inline constexpr float kMaxMetricShear = 4.0f;
// The steepest rms slope a class's tables are built for (89.4 degrees): beyond it the class's
// length per unit of u is raised until the relief is this steep, with a warning. Tracing a tile
// many periods tall costs minutes per table set (an amplitude of 1e6 took 467 s) and describes a
// bed of needles that no real surface is.
inline constexpr float kMaxTableSlope = 100.0f;

// The classes for the metrics sampled on a material's surfaces: samples binned by their shape
// quantized to stepOctaves in a and stepOctaves / 2 in b; each bin's class has the bin's mean shape
// (geometric in a; exactly the identity when that is within 1e-3 of it) and metricClasses over the
// bin's range of lengths. Shapes are clamped to kMaxMetricStretch and kMaxMetricShear first. Past
// kMaxMetricClasses the step is doubled until they fit; `stepUsed` (may be null) receives the step
// that was used.
std::vector<MetricClass> metricClassesFor(std::span<const MetricClass> samples, float stepOctaves,
                                          float* stepUsed = nullptr);

// The metric classes that cover lengths per unit of u in [lo, hi]: one class at sqrt(lo hi) when
// hi / lo < 1 + 1e-3, else a geometric series from lo to hi with ratio at most 2^stepOctaves.
std::vector<float> metricClasses(float lo, float hi, float stepOctaves);

// True when the material has anything for the relief renderers (levels or an NDF).
inline bool hasRelief(const Material& m) { return !m.relief.empty() || m.ndf.present; }

// Builds each level's slope pyramid: a height table's own texels (rounded up to powers of two), or
// a procedural source sampled 4 times per period of its highest frequency (at most 2048 x 2048).
void buildSlopePyramids(MaterialRelief& relief);

}  // namespace meso
