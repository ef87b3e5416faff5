// The configurations `meso trade` sweeps (DESIGN.md section 7): the hybrid over D x spp at the
// scene's dicing rate and over dicing rate x spp at the scene's D, displacement alone over dicing
// rate x spp, and the full-displacement reference levels.
#pragma once

#include "meso/scene/scene.h"

#include <string>
#include <vector>

namespace meso::trade {

enum class Kind { Reference, Hybrid, Displacement };

struct Configuration {
  std::string name;
  Kind kind = Kind::Hybrid;
  float D = 2.0f;  // hybrid only
  int spp = 4;
  float dicingRate = 1.0f;
  bool defaultHybrid = false;   // D and spp of the scene
  float reliefSamples = -1.0f;  // full displacement's render.relief_samples; < 0: the scene's
};

// The values swept; temporalOnly keeps only the scene's own hybrid.
struct SweepGrid {
  std::vector<float> dValues{0.5f, 1.0f, 2.0f, 4.0f};
  std::vector<int> sppValues{1, 4, 16};
  std::vector<float> dicingRates{4.0f, 2.0f, 1.0f, 0.5f};  // displacement alone
  // render.relief_samples of displacement alone, for every dicing rate: 0 dices by pixels only
  // (cheap, under-resolved where relief is sub-pixel), 4 resolves the relief there.
  std::vector<float> reliefSamples{0.0f, 4.0f};
  std::vector<float> hybridDicingRates{4.0f, 2.0f, 1.0f, 0.5f};  // the hybrid, at the scene's D
  bool temporalOnly = false;
};

// "auto" for the hybrid, "displacement" for displacement alone and the reference.
const char* algorithmName(Kind kind);

// printf's %g: the short form used in configuration names and the CSV.
std::string formatNumber(double v);

// The swept configurations without the reference levels, names unique, the scene's own hybrid
// (defaultHybrid) always among them.
std::vector<Configuration> configurations(const SweepGrid& grid, const Scene& scene);

// `base` with the configuration's algorithm, D, dicing rate and spp; throws meso::Error for a D
// the transition rejects.
Scene sceneFor(const Scene& base, const Configuration& c);

}  // namespace meso::trade
