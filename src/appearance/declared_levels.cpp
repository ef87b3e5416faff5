// A material's relief levels made from the scene's declarations (declared_levels.h).
#include "meso/appearance/declared_levels.h"

#include "meso/core/error.h"
#include "meso/core/hash.h"
#include "meso/relief/band_split.h"
#include "meso/relief/height_table.h"

#include <algorithm>
#include <cmath>
#include <memory>

namespace meso {

namespace {
// The fBm parameters a noise or solid level declares (FractalNoiseOptions, SolidNoiseOptions).
template <class Options>
Options noiseOptions(const ReliefLevelDecl& d) {
  Options o;
  o.octaves = std::max(d.octaves, 1);
  o.lacunarity = d.lacunarity;
  o.gain = d.gain;
  o.seed = d.seed;
  o.firstOctave = d.firstOctave;
  return o;
}
}  // namespace

std::unique_ptr<HeightSource> makeHeightSource(const ReliefLevelDecl& d,
                                               uint64_t memoryLimitBytes) {
  if (d.source == ReliefSource::Solid)
    return std::make_unique<SolidSlice>(noiseOptions<SolidNoiseOptions>(d));
  if (d.source == ReliefSource::Noise)
    return std::make_unique<FractalNoise>(noiseOptions<FractalNoiseOptions>(d));
  try {
    HeightTable table = HeightTable::load(d.height, d.periodic, memoryLimitBytes);
    if (d.bandCount > 1)  // one band-limited level of the image (scene/relief_bands.h)
      return std::make_unique<HeightTable>(
          bandLevelTable(table, d.bandCount, d.bandFirst, d.bandLast));
    return std::make_unique<HeightTable>(std::move(table));
  } catch (const Error& e) {
    if (d.loc.line > 0) throw Error(d.loc, "relief", e.what());
    throw;
  }
}

ReliefLevel makeReliefLevel(const ReliefLevelDecl& d, uint64_t memoryLimitBytes) {
  ReliefLevel level;
  level.source = makeHeightSource(d, memoryLimitBytes);
  level.amplitude = d.amplitude;
  level.scale = d.scale;
  if (d.source == ReliefSource::Solid) {
    // The tables trace the periodic slice, one tile every period of its lattice; the renderers
    // evaluate the (non-repeating) noise itself at d.scale cells per unit of length.
    level.solid = std::make_shared<SolidNoise>(noiseOptions<SolidNoiseOptions>(d));
    level.solidCells = d.scale;
    level.scale = d.scale / static_cast<const SolidSlice&>(*level.source).side();
  }
  level.freqPerU = d.freq > 0.0f ? d.freq : level.source->highestFrequency() * level.scale;
  const float lowest = level.source->lowestFrequency();
  level.octaveSpan = lowest > 0.0f && std::isfinite(lowest)
                         ? std::max(1.0f, level.source->highestFrequency() / lowest)
                         : 1.0f;
  level.midlevel = d.midlevel ? *d.midlevel : level.source->meanHeight();
  return level;
}

uint64_t TileRelief::fingerprint() const {
  Hasher h;
  h.value(level_.source->fingerprint()).value(level_.amplitude).value(level_.scale);
  if (lengthPerU_ != 1.0f) h.value(lengthPerU_);  // unit-metric keys as before
  return h.digest();
}

namespace {
// Owns a level and shows it as a tile.
class OwningTileRelief : public PeriodicRelief {
 public:
  explicit OwningTileRelief(ReliefLevel level) : level_(std::move(level)), tile_(level_) {}
  float height(float x, float y) const override { return tile_.height(x, y); }
  Vec2 gradient(float x, float y) const override { return tile_.gradient(x, y); }
  uint64_t fingerprint() const override { return tile_.fingerprint(); }

 private:
  ReliefLevel level_;
  TileRelief tile_;
};
}  // namespace

std::unique_ptr<PeriodicRelief> makeTileRelief(const ReliefLevelDecl& decl,
                                               uint64_t memoryLimitBytes) {
  return std::make_unique<OwningTileRelief>(makeReliefLevel(decl, memoryLimitBytes));
}

void linkImageBands(std::span<const ReliefLevelDecl> decls, std::vector<ReliefLevel>& levels,
                    uint64_t memoryLimitBytes) {
  for (size_t i = 0; i < levels.size() && i < decls.size(); ++i) {
    const ReliefLevelDecl& d = decls[i];
    if (d.source != ReliefSource::Image || d.bandCount <= 1 || d.bandLast >= d.bandCount - 1)
      continue;
    size_t end = i + 1;  // past the image's finest band
    while (end < decls.size() && decls[end].source == ReliefSource::Image &&
           decls[end].height == d.height && decls[end].bandCount == d.bandCount &&
           decls[end].bandFirst == decls[end - 1].bandLast + 1)
      ++end;
    ReliefLevelDecl sum = d;
    sum.bandLast = d.bandCount - 1;
    levels[i].partialSum =
        std::make_shared<const ReliefLevel>(makeReliefLevel(sum, memoryLimitBytes));
    levels[i].partialSumEnd = end;
  }
}

}  // namespace meso
