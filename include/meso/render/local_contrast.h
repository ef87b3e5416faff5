// Local contrast: the detail half of "consistent" (shared/DESIGN.md section 6). A renderer that
// keeps each region's mean intensity but erases the visible texture of the relief fails it.
//
// Over the kContrastBlock x kContrastBlock pixel blocks of a fixed grid that lie wholly inside one
// region (every pixel carries the region's label), with n = kContrastBlock^2 pixels a block:
//   v_b   = (1 / n) sum_p (L_p - P_b(p))^2, P_b the block's least-squares plane a + b x + c y
//           (the macro shading gradient across a block is shape, which the mean already checks,
//           not texture);
//   s2_b  = (1 / n) sum_p (L_p - L'_p)^2 / 2, L' the same render with another seed: each pixel's
//           sampling variance (pixels are sampled independently, so L - L' has twice it);
//   mu    = the mean of L over the blocks' pixels;
//   C     = sqrt(max(0, mean_b v_b - (1 - 3 / n) mean_b s2_b)) / mu.
// The plane fit leaves (n - 3) / n of independent noise in v_b, so subtracting that share of s2
// makes C an unbiased estimate (in C^2) of the contrast of the converged image: sampling noise
// does not count as detail. Without L', s2 = 0 (no correction).
//
// A region shows relief when the reference's C is at least kReliefContrastFloor; there, a
// renderer's contrast ratio C(image) / C(reference) must lie within 1 -+ kContrastTolerance.
#pragma once

#include <cstdint>
#include <vector>

namespace meso {

inline constexpr int kContrastBlock = 8;              // block side, pixels
inline constexpr double kReliefContrastFloor = 0.02;  // C of a reference that shows relief
inline constexpr double kContrastTolerance = 0.10;    // |C(image) / C(reference) - 1| allowed
// The consistency criterion's other half: every depth band's mean within this many percent of the
// reference's (`meso trade`).
inline constexpr double kConsistentBandPct = 0.5;

// The seed of the second render that measures sampling noise: another stream of every pixel's
// generator (Rng mixes the seed), so its samples are independent of the first render's.
inline uint64_t secondSeed(uint64_t seed) { return seed ^ 0x5eed5eed5eed5eedull; }

// Rec. 709 luminance, the quantity every consistency figure compares.
inline double luminance(double r, double g, double b) {
  return 0.2126 * r + 0.7152 * g + 0.0722 * b;
}

// One render's luminance (row-major, top row first) and, when known, the same render's with
// secondSeed (same size; empty: noise unknown, taken as 0).
struct LuminanceImage {
  int width = 0, height = 0;
  std::vector<float> y, ySecond;
};

// The sums C is made of, over the blocks of one region; sums of several images or regions merge.
struct ContrastSums {
  int64_t blocks = 0;
  double residual = 0.0;  // sum_b v_b
  double noise = 0.0;     // sum_b s2_b
  double mean = 0.0;      // sum_b (mean of L over block b)

  void merge(const ContrastSums& o) {
    blocks += o.blocks, residual += o.residual, noise += o.noise, mean += o.mean;
  }
  // C above; 0 without blocks or with a mean <= 0.
  double contrast() const;
  // sqrt(mean_b v_b) / mu: C before the noise correction.
  double rawContrast() const;
  // sqrt(mean_b s2_b) / mu: one pixel's sampling noise relative to the mean.
  double relativeNoise() const;
};

// Adds every block of the grid (blocks at multiples of kContrastBlock from the top-left corner)
// whose pixels all carry the same label l >= 0 to sums[l] (sums.size() > every label). label has
// one entry per pixel; -1 belongs to no region.
void addContrastBlocks(const LuminanceImage& image, const std::vector<int>& label,
                       std::vector<ContrastSums>& sums);

// C(image) / C(reference) where the reference shows relief (C >= kReliefContrastFloor), else NaN.
double contrastRatio(const ContrastSums& image, const ContrastSums& reference);

// True when the reference does not show relief (ratio NaN) or the ratio is within tolerance.
bool asDetailed(double contrastRatio);

}  // namespace meso
