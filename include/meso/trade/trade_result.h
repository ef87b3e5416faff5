// One row of trade.csv: a configuration, what it cost and its error against the reference.
#pragma once

#include "meso/trade/configuration.h"
#include "meso/trade/image_errors.h"

#include <cstddef>

namespace meso::trade {

struct TradeResult {
  Configuration config;
  double seconds = 0.0;      // prepareFrame + renderFrame, summed over the frames
  double peakRssMib = 0.0;   // VmHWM while the configuration ran
  size_t micropolygons = 0;  // the most of any frame
  double geometryMib = 0.0;  // displaced meshes and their Embree scene, the most of any frame
  ImageErrors errors;        // against the reference, averaged over the frames
  double addedMib = 0.0;     // peakRssMib above the resident memory at the start (MeasuredRender)
};

}  // namespace meso::trade
