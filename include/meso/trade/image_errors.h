// Image error of a configuration against the reference, over the beauty R, G, B of every frame.
#pragma once

#include "meso/trade/measured_render.h"

#include <vector>

namespace meso::trade {

struct ImageErrors {
  double meanAbsError = 0.0;       // mean |img - ref| over pixels and channels
  double rmse = 0.0;               // sqrt(mean (img - ref)^2) over pixels and channels
  double intensityErrorPct = 0.0;  // 100 |mean(img) - mean(ref)| / mean(ref)
};

// Each figure per frame, then averaged over the frames; images and reference pair up by frame and
// must have the same sizes (else meso::Error).
ImageErrors compareFrames(const std::vector<RgbImage>& images,
                          const std::vector<RgbImage>& reference);

}  // namespace meso::trade
