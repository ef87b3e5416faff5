// Becker & Max 1993, eq. 10: freq, the highest frequency in the bump map, measured.
#pragma once

#include "meso/core/math.h"

namespace meso {

// Highest frequency with significant energy along x (rows) and along y (columns), in cycles per
// tile: the smallest integer F such that at most `energyCutoff` of the non-constant energy of the
// averaged power spectrum lies above F. Up to 256 evenly spaced rows and columns are transformed
// (radix-2 FFT, Bluestein for other lengths). Non-periodic tables get a Hann window first, so that
// the jump between their edges does not count as detail. An axis with no variation gives 0.
Vec2 highestFrequencies(const float* texels, int width, int height, bool periodic,
                        float energyCutoff);

}  // namespace meso
