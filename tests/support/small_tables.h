// Small table sets for the appearance tests: a two-level noise relief and table resolutions that
// build in a fraction of a second, with self-shadowing.
#pragma once

#include "meso/appearance/material_tables.h"

#include <string>

namespace meso::testing {

// Two noise levels (2 and 16 tiles per unit of u) on one material.
inline Material twoNoiseLevels(const std::string& name) {
  Material m;
  m.name = name;
  ReliefLevelDecl coarse;
  coarse.source = ReliefSource::Noise;
  coarse.octaves = 2;
  coarse.amplitude = 0.04f;
  coarse.scale = 2.0f;
  coarse.seed = 3;
  ReliefLevelDecl fine = coarse;
  fine.amplitude = 0.01f;
  fine.scale = 16.0f;
  fine.seed = 5;
  m.relief = {coarse, fine};
  return m;
}

// thetaVBins view rows, 4 view-azimuth slices, shadows on.
inline TableSettings smallTableSettings(int thetaVBins = 6) {
  TableResolution q;
  q.thetaVBins = thetaVBins;
  q.thetaNBins = 24;
  q.phiBins = 12;
  q.phiVBins = 4;
  q.azimuths = 8;
  q.raysPerView = 256;
  q.meshResolution = 24;
  q.brdfThetaL = 6;
  q.brdfPhi = 6;
  TableSettings s = tableSettings(q);
  s.shadows = true;
  s.shadowing.thetaL = 7;
  s.shadowing.phi = 4;
  s.shadowing.raysPerSlice = 64;
  return s;
}

}  // namespace meso::testing
