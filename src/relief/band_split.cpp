// Becker & Max 1993, section 4.3: one bump map broken up into band-limited levels.
// Differences of nested low-passes, applied in the frequency domain.
#include "meso/relief/band_split.h"

#include "meso/core/error.h"
#include "meso/relief/fourier.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

namespace meso {
namespace {

// The low-pass transfer at radial frequency f for crossover fc: 1 below fc / sqrt(2), 0 above
// fc sqrt(2), and cos^2 over the octave between (in log2 f): C1, so the spatial ringing stays
// small, and compact, so a band holds nothing beyond half an octave past its edges.
double lowPassTransfer(double f, double fc) {
  if (f <= 0.0) return 1.0;
  const double x = std::log2(f / fc) + 0.5;  // 0 .. 1 across the transition
  if (x <= 0.0) return 1.0;
  if (x >= 1.0) return 0.0;
  const double c = std::cos(0.5 * std::numbers::pi * x);
  return c * c;
}

// The table as a complex array: itself when periodic, else mirrored to 2W x 2H so that the
// implied periodic continuation has no jump at the edges.
std::vector<Complex> extended(const HeightTable& t, size_t& ew, size_t& eh) {
  const size_t w = static_cast<size_t>(t.width()), h = static_cast<size_t>(t.heightTexels());
  const size_t m = t.periodic() ? 1 : 2;
  ew = m * w, eh = m * h;
  std::vector<Complex> data(ew * eh);
  for (size_t y = 0; y < eh; ++y)
    for (size_t x = 0; x < ew; ++x) {
      const size_t sx = x < w ? x : 2 * w - 1 - x, sy = y < h ? y : 2 * h - 1 - y;
      data[y * ew + x] = t.at(static_cast<int>(sx), static_cast<int>(sy));
    }
  return data;
}

// The low-pass of `spectrum` with crossover fc (cycles per tile), cropped to W x H.
std::vector<double> lowPass(const std::vector<Complex>& spectrum, size_t ew, size_t eh,
                            const HeightTable& t, double fc) {
  // Extended index -> cycles per tile (the extension spans ew / W tiles).
  const double sx = static_cast<double>(t.width()) / ew,
               sy = static_cast<double>(t.heightTexels()) / eh;
  std::vector<Complex> data = spectrum;
  for (size_t y = 0; y < eh; ++y)
    for (size_t x = 0; x < ew; ++x) {
      const double fx = sx * static_cast<double>(x <= ew / 2 ? x : ew - x);
      const double fy = sy * static_cast<double>(y <= eh / 2 ? y : eh - y);
      data[y * ew + x] *= lowPassTransfer(std::sqrt(fx * fx + fy * fy), fc);
    }
  dft2d(data, ew, eh, true);
  std::vector<double> out(static_cast<size_t>(t.width()) * t.heightTexels());
  for (int y = 0; y < t.heightTexels(); ++y)
    for (int x = 0; x < t.width(); ++x)
      out[static_cast<size_t>(y) * t.width() + x] = data[y * ew + x].real();
  return out;
}

HeightBand makeBand(const std::vector<double>& values, const HeightTable& t, float lowCut,
                    float highCut) {
  std::vector<float> texels(values.begin(), values.end());
  HeightTableOptions o = t.options();
  o.frequency = FrequencyEstimate::Spectral;  // Nyquist would give every band the same freq
  HeightTable band(t.width(), t.heightTexels(), std::move(texels), o);
  const float freq = band.highestFrequency();
  return HeightBand{std::move(band), freq, lowCut, highCut};
}

}  // namespace

int maxBandLevels(const HeightTable& table) {
  const int side = std::min(table.width(), table.heightTexels());
  return std::max(1, static_cast<int>(std::floor(std::log2(0.5 * side) + 1e-9)));
}

void checkBandLevels(const HeightTable& table, int numLevels) {
  if (numLevels < 1 || numLevels > 16)
    throw Error("band split: need 1 to 16 levels, got " + std::to_string(numLevels));
  const int most = maxBandLevels(table);
  if (numLevels > most) {
    char nyquist[32];
    std::snprintf(nyquist, sizeof nyquist, "%g",
                  0.5 * std::min(table.width(), table.heightTexels()));
    throw Error("band split: a " + std::to_string(table.width()) + " x " +
                std::to_string(table.heightTexels()) + " map splits into at most " +
                std::to_string(most) + (most == 1 ? " band" : " bands") +
                " of an octave or more (its frequencies reach half its shorter side, " + nyquist +
                " cycles per tile), not " + std::to_string(numLevels) +
                ": use a larger map or fewer levels");
  }
}

std::vector<HeightBand> splitBands(const HeightTable& table, int numLevels) {
  checkBandLevels(table, numLevels);
  const double nyquist = 0.5 * std::min(table.width(), table.heightTexels());
  size_t ew, eh;
  std::vector<Complex> spectrum = extended(table, ew, eh);
  dft2d(spectrum, ew, eh, false);
  // G[k], k = 0..n-1: G[0] the table, G[k] low-passed at edge[k] = nyquist^((n - k) / n).
  const int n = numLevels;
  std::vector<std::vector<double>> G(n);
  std::vector<float> edge(n + 1, 0.0f);
  G[0].assign(table.texels().begin(), table.texels().end());
  edge[0] = static_cast<float>(nyquist);
  for (int k = 1; k < n; ++k) {
    edge[k] = static_cast<float>(std::pow(std::max(nyquist, 1.0), static_cast<double>(n - k) / n));
    G[k] = lowPass(spectrum, ew, eh, table, edge[k]);
  }
  std::vector<HeightBand> bands;
  for (int m = 1; m <= n; ++m) {  // band m: G[n - m] - G[n - m + 1]; band 1: G[n - 1]
    std::vector<double> v = G[n - m];
    if (m > 1)
      for (size_t i = 0; i < v.size(); ++i) v[i] -= G[n - m + 1][i];
    bands.push_back(makeBand(v, table, m > 1 ? edge[n - m + 1] : 0.0f, edge[n - m]));
  }
  return bands;
}

}  // namespace meso
