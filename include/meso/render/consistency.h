// Becker & Max 1993, section 5.1 and Figure 6: the area-averaged intensity of a flat periodic
// patch, seen orthographically at theta_V and lit by a directional light at theta_L (or an
// environment), for each renderer.
#pragma once

#include "meso/appearance/level_tables.h"
#include "meso/appearance/periodic_tile.h"
#include "meso/render/environment_map.h"
#include "meso/scene/choices.h"  // Component, TableFormat

#include <cstdint>
#include <string>
#include <vector>

namespace meso {

struct ConsistencySettings {
  float thetaL = 0.7853982f;  // light polar angle (radians)
  float phi = 0.0f;           // phi_V - phi_L (radians)
  Component component = Component::Diffuse;
  float phong = 20.0f;  // exponent for the specular component
  int azimuths = 64;    // view azimuths averaged (the tables are azimuth averages too)
  int samplesPerAzimuth = 4096;
  uint64_t seed = 1;
  // Relief self-shadowing (DESIGN.md section 6): displacement traces a shadow ray towards L at
  // every visible hit, redistribution and brdf are scaled by the level's ShadowingTable (which the
  // tables must then hold); bump, the inconsistent baseline, stays unshadowed.
  bool shadows = false;
  // Light from an environment instead of the directional light (thetaL and phi unused): each
  // sample point is lit by lightSamples importance-sampled directions (environmentLights), shared
  // by the four renderers there; directions below the patch's plane light nothing. The map's up
  // axis should be the patch's normal +z. Each renderer's value is then the luminance.
  const EnvironmentMap* environment = nullptr;
  int lightSamples = 16;
};

struct ConsistencyRow {
  float thetaV = 0.0f;
  double bump = 0.0;            // plain Blinn bump mapping
  double redistribution = 0.0;  // bump normals mapped by R_thetaV
  double brdf = 0.0;            // the level's BRDF table
  double displacement = 0.0;    // rays at the displaced periodic relief, shaded with Blinn normals
};

// The table of rows: CSV with the header exactly `theta_v,bump,redistribution,brdf,displacement`
// (theta_v in degrees), or a Markdown table with the largest pairwise difference of redistribution,
// brdf and displacement per row. normalizeTo > 0 scales every value so that bump at the first row
// (theta_V = 0 when asked first) equals it, like the paper's Figure 6 (128).
std::string formatConsistency(const std::vector<ConsistencyRow>& rows, TableFormat format,
                              double normalizeTo);

// Largest |a - b| / b over the pairs of redistribution, brdf and displacement, as a fraction.
double worstPairwiseDifference(const ConsistencyRow& r);

// Unit white directional light, kd = 1 and/or ks = 1, ka = 0. Deterministic for a seed.
ConsistencyRow measureConsistency(const PeriodicRelief& relief, const PeriodicTile& tile,
                                  const LevelTables& tables, float thetaV,
                                  const ConsistencySettings& s);

}  // namespace meso
