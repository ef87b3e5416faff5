// The swept configurations of `meso trade` (see configuration.h).
#include "meso/trade/configuration.h"

#include "meso/render/transition.h"

#include <fmt/format.h>

namespace meso::trade {

const char* algorithmName(Kind kind) { return kind == Kind::Hybrid ? "auto" : "displacement"; }

std::string formatNumber(double v) { return fmt::format("{:g}", v); }

std::vector<Configuration> configurations(const SweepGrid& grid, const Scene& scene) {
  std::vector<Configuration> list;
  const float sceneD = scene.render.transition.D, sceneRate = scene.render.dicingRate;
  const int sceneSpp = scene.camera.spp;
  const auto hybrid = [&](float D, float rate, int spp) {
    return Configuration{.name = "hybrid_D" + formatNumber(D) + "_r" + formatNumber(rate) + "_spp" +
                                 std::to_string(spp),
                         .kind = Kind::Hybrid,
                         .D = D,
                         .spp = spp,
                         .dicingRate = rate,
                         .defaultHybrid = D == sceneD && spp == sceneSpp && rate == sceneRate};
  };
  const auto add = [&](const Configuration& c) {
    for (const Configuration& other : list)
      if (other.name == c.name) return;
    list.push_back(c);
  };
  if (!grid.temporalOnly) {
    for (float D : grid.dValues)
      for (int spp : grid.sppValues) add(hybrid(D, sceneRate, spp));
    for (float rate : grid.hybridDicingRates)
      for (int spp : grid.sppValues) add(hybrid(sceneD, rate, spp));
  }
  add(hybrid(sceneD, sceneRate, sceneSpp));  // the summary's configuration
  if (!grid.temporalOnly)
    for (float samples : grid.reliefSamples)
      for (float rate : grid.dicingRates)
        for (int spp : grid.sppValues)
          add({.name = "displacement_r" + formatNumber(rate) + "_rs" + formatNumber(samples) +
                       "_spp" + std::to_string(spp),
               .kind = Kind::Displacement,
               .D = 0.0f,
               .spp = spp,
               .dicingRate = rate,
               .reliefSamples = samples});
  return list;
}

Scene sceneFor(const Scene& base, const Configuration& c) {
  Scene scene = base;
  scene.render.algorithm = c.kind == Kind::Hybrid ? Algorithm::Auto : Algorithm::Displacement;
  if (c.kind == Kind::Hybrid) scene.render.transition.D = c.D;
  scene.render.dicingRate = c.dicingRate;
  if (c.reliefSamples >= 0.0f) scene.render.reliefSamples = c.reliefSamples;
  scene.camera.spp = c.spp;
  validateTransitionSettings(scene.render.transition, "--d-values");
  return scene;
}

}  // namespace meso::trade
