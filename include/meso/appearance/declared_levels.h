// A material's relief levels made from the scene's declarations (height images, their bands, noise
// and solid noise), and one period of a level as the table builders see it.
#pragma once

#include "meso/appearance/histogram_builder.h"
#include "meso/core/memory_budget.h"
#include "meso/relief/height_source.h"
#include "meso/relief/relief_level.h"
#include "meso/scene/scene.h"

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace meso {

// Throws meso::Error naming the level's file and line for unreadable height images and for images
// larger than memoryLimitBytes allows.
std::unique_ptr<HeightSource> makeHeightSource(
    const ReliefLevelDecl& decl, uint64_t memoryLimitBytes = defaultMemoryLimitBytes());
ReliefLevel makeReliefLevel(const ReliefLevelDecl& decl,
                            uint64_t memoryLimitBytes = defaultMemoryLimitBytes());
// Sets partialSum and partialSumEnd of every band of a height image that finer bands of the same
// image continue (levels[i] made from decls[i]).
void linkImageBands(std::span<const ReliefLevelDecl> decls, std::vector<ReliefLevel>& levels,
                    uint64_t memoryLimitBytes = defaultMemoryLimitBytes());

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
std::unique_ptr<PeriodicRelief> makeTileRelief(
    const ReliefLevelDecl& decl, uint64_t memoryLimitBytes = defaultMemoryLimitBytes());

}  // namespace meso
