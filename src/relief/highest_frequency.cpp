// Becker & Max 1993, eq. 10: freq, the highest frequency in the bump map, from power spectra.
#include "meso/relief/highest_frequency.h"

#include "meso/relief/fourier.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace meso {
namespace {

// Power by frequency (cycles per tile, 0..n/2) summed over `count` evenly spaced lines of length n;
// line s starts at texel (s * lines / count) * lineStep and steps by `stride`; `raw` accumulates
// the lines' total energy.
std::vector<double> linePower(const float* texels, size_t n, size_t lines, size_t lineStep,
                              size_t stride, bool periodic, double& raw) {
  std::vector<double> power(n / 2 + 1, 0.0);
  const size_t count = std::min<size_t>(lines, 256);
  const Dft dft(n);
  std::vector<Complex> work;
  for (size_t s = 0; s < count; ++s) {
    const float* line = texels + (s * lines / count) * lineStep;
    double mean = 0.0;
    for (size_t j = 0; j < n; ++j) mean += line[j * stride];
    mean /= static_cast<double>(n);
    work.assign(n, Complex(0.0));
    for (size_t j = 0; j < n; ++j) {
      const double hann =
          periodic ? 1.0 : 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * (j + 0.5) / n);
      work[j] = hann * (line[j * stride] - mean);
      raw += static_cast<double>(line[j * stride]) * line[j * stride];
    }
    dft.forward(work);
    for (size_t k = 1; k < n; ++k) power[std::min(k, n - k)] += std::norm(work[k]);
  }
  return power;
}

// The smallest F with at most `cutoff` of the non-constant energy above it; 0 for a flat line.
float cutoffFrequency(const std::vector<double>& power, double raw, float cutoff) {
  double total = 0.0;
  for (size_t f = 1; f < power.size(); ++f) total += power[f];
  // Below 1e-12 of the lines' energy (heights varying by a millionth of their size) an axis holds
  // only float rounding, which is white: it has no detail, not detail up to its Nyquist limit (a
  // band of a split image that varies along x only measured 31 cycles along y of 32).
  if (!(total > 1e-12 * raw) || !std::isfinite(total)) return 0.0f;
  double tail = 0.0;
  for (size_t f = power.size() - 1; f >= 1; --f) {
    if (tail + power[f] > static_cast<double>(cutoff) * total) return static_cast<float>(f);
    tail += power[f];
  }
  return 1.0f;
}

}  // namespace

Vec2 highestFrequencies(const float* texels, int width, int height, bool periodic,
                        float energyCutoff) {
  if (width <= 0 || height <= 0) return Vec2(0.0f);
  const size_t w = static_cast<size_t>(width), h = static_cast<size_t>(height);
  Vec2 f(0.0f);
  if (w > 1) {
    double raw = 0.0;
    const std::vector<double> p = linePower(texels, w, h, w, 1, periodic, raw);  // rows: along x
    f.x = cutoffFrequency(p, raw, energyCutoff);
  }
  if (h > 1) {
    double raw = 0.0;
    const std::vector<double> p = linePower(texels, h, w, 1, w, periodic, raw);  // columns: along y
    f.y = cutoffFrequency(p, raw, energyCutoff);
  }
  return f;
}

}  // namespace meso
