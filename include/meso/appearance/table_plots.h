// The data of `meso tables`' plots: a level's tables as CSV, one row per cell, which
// tools/plot_tables.py draws with matplotlib (a panel per theta_V with axes, labels and a colour
// bar). Angles in degrees.
#pragma once

#include "meso/appearance/brdf_table.h"
#include "meso/appearance/visible_normal_histogram.h"

#include <string>

namespace meso {

// "theta_v_deg,theta_n_deg,phi_deg,density": every theta_N and phi_{N-V} bin centre of every
// theta_V slice (with view-azimuth slices, the phi_V slice nearest 0), density = the bin's mass
// over its solid angle (per steradian).
std::string histogramCsv(const VisibleNormalHistogram& distr);

// "theta_v_deg,theta_l_deg,phi_deg,diffuse,specular": every theta_L node in [0, 90] and phi_{V-L}
// node in [0, 180] of every theta_V slice (with view-azimuth slices, the phi_V slice nearest 0).
std::string brdfCsv(const BrdfTable& brdf);

}  // namespace meso
