// Local contrast per region, noise-corrected (see local_contrast.h; shared/DESIGN.md section 6).
#include "meso/render/local_contrast.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace meso {
namespace {

constexpr int kB = kContrastBlock;
constexpr double kPixels = static_cast<double>(kB) * kB;
// sum over the block of x'^2, x' = x - (kB - 1) / 2 (the same for y'): with x' and y' centred,
// 1, x' and y' are orthogonal over the block and the plane's coefficients are plain projections.
constexpr double kMoment = kB * (static_cast<double>(kB) * (kB * kB - 1) / 12.0);

// The block whose top-left pixel is (x0, y0), added to `sums` (its label checked by the caller).
void addBlock(const LuminanceImage& image, int x0, int y0, ContrastSums& sums) {
  const bool second = !image.ySecond.empty();
  double sum = 0.0, noise = 0.0;
  for (int y = y0; y < y0 + kB; ++y)
    for (int x = x0; x < x0 + kB; ++x) {
      const size_t i = static_cast<size_t>(y) * image.width + x;
      sum += image.y[i];
      if (second) {
        const double d = static_cast<double>(image.y[i]) - image.ySecond[i];
        noise += 0.5 * d * d;
      }
    }
  const double mean = sum / kPixels;
  double squares = 0.0, gx = 0.0, gy = 0.0;
  for (int y = 0; y < kB; ++y)
    for (int x = 0; x < kB; ++x) {
      const double d = image.y[static_cast<size_t>(y0 + y) * image.width + x0 + x] - mean;
      squares += d * d;
      gx += d * (x - 0.5 * (kB - 1)), gy += d * (y - 0.5 * (kB - 1));
    }
  // Residual of the least-squares plane: what the plane explains is gx^2 / kMoment (and gy's).
  const double residual = squares - (gx * gx + gy * gy) / kMoment;
  sums.blocks += 1;
  sums.residual += std::max(0.0, residual) / kPixels;
  sums.noise += noise / kPixels;
  sums.mean += mean;
}

// The block's label, or -1 when its pixels carry different labels (or none).
int blockLabel(const std::vector<int>& label, int width, int x0, int y0) {
  const int l = label[static_cast<size_t>(y0) * width + x0];
  if (l < 0) return -1;
  for (int y = y0; y < y0 + kB; ++y)
    for (int x = x0; x < x0 + kB; ++x)
      if (label[static_cast<size_t>(y) * width + x] != l) return -1;
  return l;
}

}  // namespace

double ContrastSums::contrast() const {
  if (blocks == 0 || !(mean > 0.0)) return 0.0;
  const double n = static_cast<double>(blocks);
  // The plane fit absorbs 3 of the block's n degrees of freedom of the noise too.
  const double signal = residual / n - (1.0 - 3.0 / kPixels) * noise / n;
  return std::sqrt(std::max(0.0, signal)) / (mean / n);
}

double ContrastSums::rawContrast() const {
  if (blocks == 0 || !(mean > 0.0)) return 0.0;
  return std::sqrt(residual / mean / mean * static_cast<double>(blocks));
}

double ContrastSums::relativeNoise() const {
  if (blocks == 0 || !(mean > 0.0)) return 0.0;
  return std::sqrt(noise / mean / mean * static_cast<double>(blocks));
}

void addContrastBlocks(const LuminanceImage& image, const std::vector<int>& label,
                       std::vector<ContrastSums>& sums) {
  for (int y0 = 0; y0 + kB <= image.height; y0 += kB)
    for (int x0 = 0; x0 + kB <= image.width; x0 += kB) {
      const int l = blockLabel(label, image.width, x0, y0);
      if (l >= 0) addBlock(image, x0, y0, sums[static_cast<size_t>(l)]);
    }
}

double contrastRatio(const ContrastSums& image, const ContrastSums& reference) {
  const double c = reference.contrast();
  if (!(c >= kReliefContrastFloor)) return std::numeric_limits<double>::quiet_NaN();
  return image.contrast() / c;
}

bool asDetailed(double contrastRatio) {
  return std::isnan(contrastRatio) || std::abs(contrastRatio - 1.0) <= kContrastTolerance;
}

}  // namespace meso
