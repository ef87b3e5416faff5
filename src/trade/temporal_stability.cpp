// Frame-to-frame change in the transition bands (see temporal_stability.h).
#include "meso/trade/temporal_stability.h"

#include "meso/render/film_layout.h"
#include "meso/trade/configuration.h"

#include <fmt/format.h>

#include <cmath>

namespace meso::trade {
namespace {

double meanAbsChange(const RgbImage& a, const RgbImage& b, int x, int y) {
  const float *pa = a.at(x, y), *pb = b.at(x, y);
  return (std::abs(pa[0] - pb[0]) + std::abs(pa[1] - pb[1]) + std::abs(pa[2] - pb[2])) / 3.0;
}

void add(TemporalBand& band, double dh, double dr) {
  ++band.pixels, band.hybridChange += dh, band.referenceChange += dr;
}

// Adds one frame pair: bands 0..3 are e1..e4, 4 any of them, 5 every surface pixel.
void addFramePair(std::vector<TemporalBand>& bands, const MeasuredRender& hybrid,
                  const MeasuredRender& reference, size_t f, float halfWidth) {
  const Image& film = hybrid.films[f];
  for (int y = 0; y < film.height; ++y)
    for (int x = 0; x < film.width; ++x) {
      if (film.at(x, y, FilmLayout::DepthZ) <= 0.0f) continue;  // no surface
      const float T = film.at(x, y, FilmLayout::T);
      const double dh = meanAbsChange(hybrid.beauty[f + 1], hybrid.beauty[f], x, y);
      const double dr = meanAbsChange(reference.beauty[f + 1], reference.beauty[f], x, y);
      bool any = false;
      for (size_t k = 0; k < 4; ++k)
        if (std::abs(T - bands[k].threshold) <= halfWidth) add(bands[k], dh, dr), any = true;
      if (any) add(bands[4], dh, dr);
      add(bands[5], dh, dr);
    }
}

double ratio(const TemporalBand& b) {
  return b.referenceChange > 0.0 ? b.hybridChange / b.referenceChange : 0.0;
}

std::string thresholdText(const TemporalBand& b) {
  return b.name != "any" && b.name != "all" ? formatNumber(b.threshold) : "";
}

}  // namespace

std::vector<TemporalBand> temporalBands(const MeasuredRender& hybrid,
                                        const MeasuredRender& reference,
                                        const TransitionSettings& t, float halfWidth) {
  std::vector<TemporalBand> bands = {{"e1", t.e1}, {"e2", t.e2},  {"e3", t.e3},
                                     {"e4", t.e4}, {"any", 0.0f}, {"all", 0.0f}};
  for (size_t f = 0; f + 1 < hybrid.films.size(); ++f)
    addFramePair(bands, hybrid, reference, f, halfWidth);
  for (TemporalBand& b : bands)
    if (b.pixels > 0)
      b.hybridChange /= static_cast<double>(b.pixels),
          b.referenceChange /= static_cast<double>(b.pixels);
  return bands;
}

std::string temporalCsv(const std::vector<TemporalBand>& bands, float halfWidth) {
  std::string s =
      "band,threshold,half_width,pixels,hybrid_mean_abs_change,reference_mean_abs_change,ratio\n";
  for (const TemporalBand& b : bands)
    s += fmt::format("{},{},{:g},{},{:.6g},{:.6g},{:.4g}\n", b.name, thresholdText(b), halfWidth,
                     b.pixels, b.hybridChange, b.referenceChange, ratio(b));
  return s;
}

std::string temporalTable(const std::vector<TemporalBand>& bands, float halfWidth) {
  std::string s = fmt::format(
      "temporal stability: mean |beauty(f+1) - beauty(f)| in bands |T - e| <= {:g} of the hybrid\n"
      "  {:<5} {:>9} {:>10} {:>12} {:>12} {:>8}\n",
      halfWidth, "band", "threshold", "pixels", "hybrid", "reference", "ratio");
  for (const TemporalBand& b : bands)
    s += fmt::format("  {:<5} {:>9} {:>10} {:>12.5g} {:>12.5g} {:>8.3g}\n", b.name,
                     thresholdText(b), b.pixels, b.hybridChange, b.referenceChange, ratio(b));
  return s;
}

}  // namespace meso::trade
