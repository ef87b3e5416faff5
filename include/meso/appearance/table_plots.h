// Pictures of a level's tables for `meso tables`: heat maps laid out as panels, one per theta_V.
#pragma once

#include "meso/appearance/brdf_table.h"
#include "meso/appearance/visible_normal_histogram.h"
#include "meso/core/image.h"

namespace meso {

// One panel per theta_V slice: theta_N across (0 at the left, 90 degrees at the right), phi_{N-V}
// down (-180 at the top), colour = probability density per solid angle, scaled per panel.
Image plotHistogram(const VisibleNormalHistogram& distr, int cellPixels = 6);

// One panel per theta_V slice: theta_L across, phi_{V-L} down; top row of panels diffuse, bottom
// row specular, each on one colour scale shared by all its panels.
Image plotBrdf(const BrdfTable& brdf, int cellPixels = 8);

}  // namespace meso
