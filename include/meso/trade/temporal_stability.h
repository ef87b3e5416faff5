// Temporal stability of the hybrid near its thresholds (`meso trade --temporal`): for consecutive
// frames f, f+1 of the default hybrid and of the reference, the mean over R, G, B of
// |beauty(f+1) - beauty(f)| over the pixels whose T.Y in the hybrid's frame f lies within a half
// width of e1, e2, e3 or e4 (pixels where no surface was hit are left out), pooled over the pairs.
#pragma once

#include "meso/scene/scene.h"
#include "meso/trade/measured_render.h"

#include <cstddef>
#include <string>
#include <vector>

namespace meso::trade {

struct TemporalBand {
  std::string name;  // e1..e4, "any" (near any threshold) or "all" (every surface pixel)
  float threshold = 0.0f;
  size_t pixels = 0;
  double hybridChange = 0.0, referenceChange = 0.0;  // mean |change| over the band's pixels
};

// `hybrid` must hold its films (MeasureOptions::keepFilms), renderFrame's (FilmLayout): T and depth
// are read from their channels.
std::vector<TemporalBand> temporalBands(const MeasuredRender& hybrid,
                                        const MeasuredRender& reference,
                                        const TransitionSettings& t, float halfWidth);

// temporal.csv: band,threshold,half_width,pixels,hybrid_mean_abs_change,...,ratio.
std::string temporalCsv(const std::vector<TemporalBand>& bands, float halfWidth);

// The same as a table for the terminal.
std::string temporalTable(const std::vector<TemporalBand>& bands, float halfWidth);

}  // namespace meso::trade
