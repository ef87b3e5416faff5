// Becker & Max 1993, section 4.3: one bump map broken up into band-limited levels.
// Differences of nested low-passes, applied in the frequency domain.
#include "meso/relief/band_split.h"

#include "meso/core/error.h"
#include "meso/relief/fourier.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
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

// The crossover of low-pass k of n (splitBands' edge[k]): nyquist^((n - k) / n) cycles per tile.
float crossover(double nyquist, int k, int n) {
  return static_cast<float>(std::pow(std::max(nyquist, 1.0), static_cast<double>(n - k) / n));
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
    const std::string nyquist =
        fmt::format("{:g}", 0.5 * std::min(table.width(), table.heightTexels()));
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
    edge[k] = crossover(nyquist, k, n);
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

namespace meso {
namespace {

// |grad h|^2 per texel in texel units, by central differences (wrapped or clamped as the table).
std::vector<double> slopeSquares(const HeightTable& t) {
  const int w = t.width(), h = t.heightTexels();
  std::vector<double> out(static_cast<size_t>(w) * h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const double gx = 0.5 * (t.texel(i + 1, j) - t.texel(i - 1, j));
      const double gy = 0.5 * (t.texel(i, j + 1) - t.texel(i, j - 1));
      out[static_cast<size_t>(j) * w + i] = gx * gx + gy * gy;
    }
  return out;
}

// The slope energy of a table: the mean of |grad h|^2.
double slopeEnergy(const HeightTable& t) {
  const std::vector<double> s = slopeSquares(t);
  double sum = 0.0;
  for (double v : s) sum += v;
  return sum / static_cast<double>(s.size());
}

// slopeSquares of the sum of bands first..last.
std::vector<double> slopeSquares(const std::vector<HeightBand>& bands, int first, int last) {
  const HeightTable& t = bands.front().table;
  std::vector<float> sum(t.texels().size(), 0.0f);
  for (int b = first; b <= last; ++b)
    for (size_t k = 0; k < sum.size(); ++k) sum[k] += bands[b].table.texels()[k];
  return slopeSquares(HeightTable(t.width(), t.heightTexels(), std::move(sum), t.options()));
}

// Pearson's correlation of two equally long series (0 when either is constant).
double correlation(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double mx = 0.0, my = 0.0;
  for (size_t k = 0; k < x.size(); ++k) mx += x[k], my += y[k];
  mx /= n, my /= n;
  double sxy = 0.0, sxx = 0.0, syy = 0.0;
  for (size_t k = 0; k < x.size(); ++k) {
    const double a = x[k] - mx, b = y[k] - my;
    sxy += a * b, sxx += a * a, syy += b * b;
  }
  return sxx > 0.0 && syy > 0.0 ? sxy / std::sqrt(sxx * syy) : 0.0;
}

}  // namespace

BandPlan planBands(const HeightTable& table, int requested, int maxLevels, double minSlopeShare) {
  BandPlan plan;
  const int most = maxBandLevels(table);
  plan.bands = requested > 0 ? std::min(requested, most) : most;
  maxLevels = std::max(maxLevels, 1);
  if (plan.bands == 1) {
    plan.levels = {BandLevel{0, 0, 1.0}};
    return plan;
  }
  const std::vector<HeightBand> bands = splitBands(table, plan.bands);
  double total = 0.0;
  for (const HeightBand& b : bands) {
    plan.levels.push_back({static_cast<int>(plan.levels.size()),
                           static_cast<int>(plan.levels.size()), slopeEnergy(b.table)});
    total += plan.levels.back().slopeShare;
  }
  for (BandLevel& l : plan.levels) l.slopeShare = total > 0.0 ? l.slopeShare / total : 0.0;
  // Merge the weakest level into its neighbour (the finer one, or the coarser one for the finest)
  // until every level has its share and there are at most maxLevels. Summing bands is exact (the
  // split is linear), so the shares of merged bands add.
  while (plan.levels.size() > 1) {
    size_t weakest = 0;
    for (size_t k = 1; k < plan.levels.size(); ++k)
      if (plan.levels[k].slopeShare < plan.levels[weakest].slopeShare) weakest = k;
    if (plan.levels[weakest].slopeShare >= minSlopeShare &&
        plan.levels.size() <= static_cast<size_t>(maxLevels))
      break;
    const size_t into = weakest + 1 < plan.levels.size() ? weakest + 1 : weakest - 1;
    BandLevel& target = plan.levels[into];
    target.first = std::min(target.first, plan.levels[weakest].first);
    target.last = std::max(target.last, plan.levels[weakest].last);
    target.slopeShare += plan.levels[weakest].slopeShare;
    plan.levels.erase(plan.levels.begin() + static_cast<std::ptrdiff_t>(weakest));
  }
  // Neighbours of about one frequency are one level: a wave at a crossover falls into both bands
  // (half its amplitude in each), and two levels with the same T would only cost twice.
  const auto freqOf = [&](const BandLevel& l) {
    std::vector<float> texels(table.texels().size(), 0.0f);
    for (int b = l.first; b <= l.last; ++b)
      for (size_t t = 0; t < texels.size(); ++t) texels[t] += bands[b].table.texels()[t];
    HeightTableOptions o = table.options();
    o.frequency = FrequencyEstimate::Spectral;
    return HeightTable(table.width(), table.heightTexels(), std::move(texels), o)
        .highestFrequency();
  };
  const auto mergeInto = [&](size_t k) {  // level k joins level k - 1
    plan.levels[k - 1].last = plan.levels[k].last;
    plan.levels[k - 1].slopeShare += plan.levels[k].slopeShare;
    plan.levels[k - 1].coupled = plan.levels[k - 1].coupled || plan.levels[k].coupled;
    plan.levels.erase(plan.levels.begin() + static_cast<std::ptrdiff_t>(k));
  };
  for (size_t k = 1; k < plan.levels.size();) {
    if (freqOf(plan.levels[k]) < kMinLevelFrequencyRatio * freqOf(plan.levels[k - 1]))
      mergeInto(k);
    else
      ++k;
  }
  // Finer bands whose slopes sit where the coarser ones' do (the edges of bricks or tiles, whose
  // octaves are phase-aligned) are not independent of them, as drawing them from tables on a
  // raised coarser level assumes (eq. 1): such a split is not made. Split after the finest level
  // first, so that a correlated tail joins as a whole.
  for (size_t k = plan.levels.size(); k-- > 1;) {
    const double r = correlation(slopeSquares(bands, 0, plan.levels[k - 1].last),
                                 slopeSquares(bands, plan.levels[k].first, plan.bands - 1));
    if (r > kMaxBandSlopeCorrelation) {
      plan.levels[k].coupled = true;
      mergeInto(k);
    }
  }
  // A level of coupled bands is displaced and redistributed as a whole where its coarsest band
  // with a share of the slope spans enough pixels: that band's frequency is its T's.
  for (BandLevel& l : plan.levels) {
    if (!l.coupled) continue;
    int b = l.first;
    while (b < l.last && slopeEnergy(bands[b].table) < minSlopeShare * total) ++b;
    l.transitionFrequency = bands[b].freq;
  }
  return plan;
}

HeightTable bandLevelTable(const HeightTable& table, int bands, int first, int last) {
  HeightTableOptions o = table.options();
  o.frequency = FrequencyEstimate::Spectral;
  first = std::max(first, 0), last = std::min(last, bands - 1);
  if (bands <= 1 || (first == 0 && last == bands - 1))
    return HeightTable(table.width(), table.heightTexels(), table.texels(), o);
  checkBandLevels(table, bands);
  // Bands first..last of splitBands telescope to G[n - 1 - last] - G[n - first] (G[0] the table,
  // G[n] zero): two low-passes instead of the whole split.
  const int n = bands;
  const double nyquist = 0.5 * std::min(table.width(), table.heightTexels());
  size_t ew, eh;
  std::vector<Complex> spectrum = extended(table, ew, eh);
  dft2d(spectrum, ew, eh, false);
  const auto G = [&](int k) {
    if (k == 0) return std::vector<double>(table.texels().begin(), table.texels().end());
    if (k == n) return std::vector<double>(table.texels().size(), 0.0);
    return lowPass(spectrum, ew, eh, table, crossover(nyquist, k, n));
  };
  const std::vector<double> upper = G(n - 1 - last), lower = G(n - first);
  std::vector<float> texels(upper.size());
  for (size_t t = 0; t < texels.size(); ++t) texels[t] = static_cast<float>(upper[t] - lower[t]);
  return HeightTable(table.width(), table.heightTexels(), std::move(texels), o);
}

}  // namespace meso
