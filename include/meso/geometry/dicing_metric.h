// How the length of an edge in pixels is measured for dicing (the scene key render.dicing_metric;
// its names are in meso/scene/choices.h).
#pragma once

namespace meso {

enum class DicingMetric {
  // World length over the pixel footprint at the edge's depth (ScreenMetric::footprintLength):
  // micropolygons are about dicingRate pixel footprints long in every direction, also along the
  // view direction at grazing angles, where relief seen edge-on needs them.
  Isotropic,
  // Foreshortened screen length of the edge (ScreenMetric::projectedLength): fewer micropolygons
  // at grazing angles, where they are many pixels deep, so displacement there is under-resolved.
  Projected,
};

}  // namespace meso
