// Image error of a configuration against the reference, over the beauty R, G, B of every frame.
#pragma once

#include "meso/trade/measured_render.h"

#include <limits>
#include <vector>

namespace meso::trade {

struct ImageErrors {
  double meanAbsError = 0.0;       // mean |img - ref| over pixels and channels
  double rmse = 0.0;               // sqrt(mean (img - ref)^2) over pixels and channels
  double intensityErrorPct = 0.0;  // 100 |mean(img) - mean(ref)| / mean(ref)
  // Intensity consistency: over the pixels where the reference hits a surface, split into
  // kDepthBands bands of the reference's depth (equal pixel counts, near to far), the signed
  // 100 (mean(img) - mean(ref)) / mean(ref) of the band where it is largest in magnitude (each
  // band averaged over the frames). 0 without the reference's depth.
  double worstBandPct = 0.0;
  // Detail (render/local_contrast.h): in each of those depth bands where the reference shows
  // relief, the image's local contrast over the reference's (blocks pooled over the frames); the
  // ratio furthest from 1, NaN when no band shows relief or without the reference's depth.
  double worstContrastRatio = std::numeric_limits<double>::quiet_NaN();
};

constexpr int kDepthBands = 5;

// Each figure per frame, then averaged over the frames; images and reference pair up by frame and
// must have the same sizes (else meso::Error). referenceDepth: per frame and pixel, the distance
// of the reference's hit, 0 for none (empty: no band figures). imagesSecond and referenceSecond:
// the same frames rendered with the second seed, whose difference measures the sampling noise the
// local contrast leaves out (empty: no noise correction).
ImageErrors compareFrames(const std::vector<RgbImage>& images,
                          const std::vector<RgbImage>& reference,
                          const std::vector<std::vector<float>>& referenceDepth = {},
                          const std::vector<RgbImage>& imagesSecond = {},
                          const std::vector<RgbImage>& referenceSecond = {});

// The same for two measured renders (beauty, second beauty, the reference's depth).
ImageErrors compareRenders(const MeasuredRender& image, const MeasuredRender& reference);

// The change of one frame's rgb from b to a over `hits` (pixel indices sorted near to far): per
// depth band (kDepthBands equal counts) 100 (sum a - sum b) / sum a added to bandPct; returns the
// rmse over those pixels in percent of a's mean there.
double frameChange(const std::vector<float>& a, const std::vector<float>& b,
                   const std::vector<size_t>& hits, std::vector<double>& bandPct);

}  // namespace meso::trade
