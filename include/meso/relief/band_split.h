// Becker & Max 1993, section 4.3: one height map broken up into band-limited levels.
#pragma once

#include "meso/relief/height_table.h"

#include <vector>

namespace meso {

// One band-limited level, low to high frequency. table.highestFrequency() == freq.
struct HeightBand {
  HeightTable table;
  float freq;     // measured highest frequency, cycles per tile (Spectral estimate)
  float lowCut;   // crossover to the band below, cycles per tile (0 for the lowest band)
  float highCut;  // crossover to the band above (the Nyquist frequency for the highest band)
};

// Differences of nested low-passes: L_0 = the table, L_k = the table low-passed at the crossover
// f_k = nyquist^((n - k) / n) cycles per tile (geometric crossovers between 1 cycle and the
// Nyquist frequency min(W, H) / 2). Band 1 is L_{n-1}, band m is L_{n-m} - L_{n-m+1}, so the bands
// sum to the table within float rounding, and band 1 keeps the mean. The low-pass is radial in the
// frequency domain: 1 below f_k / sqrt(2), 0 above f_k sqrt(2), cos^2 in log2(f) between (half
// amplitude at f_k). Periodic tables are transformed as they are; clamped ones are mirrored to
// 2W x 2H first so that their edges do not ring. Every band keeps the table's size and options,
// with a Spectral frequency estimate. Throws checkBandLevels's error first.
std::vector<HeightBand> splitBands(const HeightTable& table, int numLevels);

// Throws meso::Error, saying why, for numLevels < 1 or > 16, or above maxBandLevels(table).
void checkBandLevels(const HeightTable& table, int numLevels);

// The most bands `table` splits into with each band at least an octave wide (the low-pass's
// transition is an octave, so a narrower band would hold no frequency of its own):
// floor(log2(nyquist)), at least 1. A 1 x 1 map has one band (itself), a 16 x 16 map 3.
int maxBandLevels(const HeightTable& table);

}  // namespace meso

namespace meso {

// A height image as levels (DESIGN.md section 1): its octave bands, neighbours merged where a band
// carries too little of the image's slope energy to be a level of its own.
struct BandLevel {
  int first = 0;  // bands first..last (0-based, coarse to fine) summed into the level
  int last = 0;
  double slopeShare = 1.0;  // the level's share of the sum of the bands' slope energies
  // Bands merged because their slopes correlate (kMaxBandSlopeCorrelation): the level's T then
  // follows transitionFrequency (cycles per tile), the highest frequency of its coarsest band
  // with a share of the slope energy, not its finest texels. 0 otherwise.
  bool coupled = false;
  float transitionFrequency = 0.0f;
};
struct BandPlan {
  int bands = 1;                  // octave bands the image is split into (splitBands' numLevels)
  std::vector<BandLevel> levels;  // coarse to fine, covering 0..bands-1 once
};

// The default minimum slope share of a level: a band below it joins its finer neighbour (the
// finest joins its coarser one). Coarse bands of an image hold its large heights but little
// slope, so they ride with the first band that matters for shading.
inline constexpr double kMinBandSlopeShare = 0.05;

// Neighbouring levels whose highest frequencies (Spectral estimates) are closer than this ratio
// are merged: they hold the same waves.
inline constexpr float kMinLevelFrequencyRatio = 1.41421356f;

// The largest correlation (Pearson, over texels) between |grad h|^2 of the levels above a split
// and of the bands below it for which the split is made. Measured on 256^2 maps: a random field
// with a 1/f spectrum 0.02 or less at every split, smooth blobs with scratches 0.16 or less,
// sharp-edged bricks 0.19 between their coarse octaves and 0.50 to 0.60 below.
inline constexpr double kMaxBandSlopeCorrelation = 0.1;

// Splits `table` into min(requested, maxBandLevels) bands (requested 0: maxBandLevels), at most
// maxLevels levels after merging (the weakest neighbours merged first), then neighbours closer in
// frequency than kMinLevelFrequencyRatio merged, then levels whose slopes correlate with the
// coarser ones' (kMaxBandSlopeCorrelation) merged into them. The slope energy of a band is the mean
// of |grad h|^2 over its texels (central differences).
BandPlan planBands(const HeightTable& table, int requested, int maxLevels,
                   double minSlopeShare = kMinBandSlopeShare);

// The level bands first..last of `bands` of `table` summed: a table of the same size and options
// (a Spectral frequency estimate), as the renderer uses it.
HeightTable bandLevelTable(const HeightTable& table, int bands, int first, int last);

}  // namespace meso
