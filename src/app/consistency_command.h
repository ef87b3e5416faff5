// `meso consistency`: the paper's Figure 6 for any relief.
#pragma once

#include "command.h"

#include "meso/scene/choices.h"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace meso::app {

// Its options; the patch table goes to stdout.
struct ConsistencyCommandOptions {
  // A scene: Figure 6 for the whole scene (each renderer against a displacement reference, per
  // object and per band of rows) instead of the periodic patch.
  std::filesystem::path scene;
  std::vector<std::string> set;  // SCENE: --set KEY=VALUE, in order
  int bands = 6;
  float referenceDicing = 0.25f;
  int referenceSpp = 0;
  std::vector<Algorithm> algorithms{Algorithm::Bump, Algorithm::Redistribution, Algorithm::Brdf,
                                    Algorithm::Auto};
  std::filesystem::path height;  // empty: procedural noise
  float amplitude = 0.05f;
  float scale = 1.0f;
  int octaves = 3;
  unsigned seed = 1;
  std::vector<float> thetaV{0.0f, 30.0f, 60.0f, 80.0f};  // degrees
  float thetaL = 45.0f;
  float phi = 0.0f;
  Component component = Component::Diffuse;
  float phong = 20.0f;
  TableFormat format = TableFormat::Csv;
  double normalize = 0.0;
  int samples = 4096;
  int azimuths = 64;
  RedistributionVariant variant = RedistributionVariant::Conditional;
  std::filesystem::path cacheDir;  // empty: the default cache folder
  bool noCache = false;
  bool shadows = false;  // relief self-shadowing in every renderer but bump
  int shadowRays = 0;    // visible hits per slice of the shadowing table; 0: the renderer's default
  // The patch lit by an environment instead of the directional light: a latitude-longitude map,
  // or "uniform" for a uniform white sky; its up axis is the patch's normal.
  std::string environment;
  float environmentRotation = 0.0f;  // degrees about the patch's normal
  int lightSamples = 16;             // environment directions per sample point
  int phiVBins =
      0;  // view-azimuth slices of the tables; 0: 1 (the paper's), 16 with an environment
};

// The `consistency` command, registered on `cli` with its options.
std::unique_ptr<Command> makeConsistencyCommand(CLI::App& cli);

}  // namespace meso::app
