// Image error against the reference (see image_errors.h).
#include "meso/trade/image_errors.h"

#include "meso/core/error.h"

#include <algorithm>
#include <cmath>

namespace meso::trade {
namespace {

double meanValue(const std::vector<float>& values) {
  double sum = 0.0;
  for (float v : values) sum += v;
  return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

ImageErrors compareFrame(const RgbImage& image, const RgbImage& reference) {
  if (image.width != reference.width || image.height != reference.height ||
      image.rgb.size() != reference.rgb.size())
    throw Error("trade: internal: comparing images of different sizes");
  double absSum = 0.0, squares = 0.0;
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    const double d = std::abs(static_cast<double>(image.rgb[i]) - reference.rgb[i]);
    absSum += d, squares += d * d;
  }
  const double n = static_cast<double>(image.rgb.size());
  const double mi = meanValue(image.rgb), mr = meanValue(reference.rgb);
  return {n > 0.0 ? absSum / n : 0.0, n > 0.0 ? std::sqrt(squares / n) : 0.0,
          mr > 0.0 ? 100.0 * std::abs(mi - mr) / mr : (mi == mr ? 0.0 : 100.0)};
}

}  // namespace

double frameChange(const std::vector<float>& a, const std::vector<float>& b,
                   const std::vector<size_t>& hits, std::vector<double>& bandPct) {
  double sumA = 0.0, squares = 0.0;
  for (int band = 0; band < kDepthBands; ++band) {
    double bandA = 0.0, bandB = 0.0;
    for (size_t k = hits.size() * band / kDepthBands; k < hits.size() * (band + 1) / kDepthBands;
         ++k)
      for (int c = 0; c < 3; ++c) {
        const double va = a[3 * hits[k] + c], vb = b[3 * hits[k] + c];
        bandA += va, bandB += vb, squares += (va - vb) * (va - vb);
      }
    sumA += bandA;
    bandPct[band] += bandA > 0.0 ? 100.0 * (bandA - bandB) / bandA : 0.0;
  }
  const double n = 3.0 * static_cast<double>(hits.size());
  return sumA > 0.0 ? 100.0 * std::sqrt(squares / n) / (sumA / n) : 0.0;
}

ImageErrors compareFrames(const std::vector<RgbImage>& images,
                          const std::vector<RgbImage>& reference,
                          const std::vector<std::vector<float>>& referenceDepth) {
  if (images.size() != reference.size() || images.empty())
    throw Error("trade: internal: comparing different numbers of frames");
  if (!referenceDepth.empty() && referenceDepth.size() != reference.size())
    throw Error("trade: internal: reference depth for a different number of frames");
  ImageErrors sum;
  std::vector<double> bandPct(kDepthBands, 0.0);
  for (size_t f = 0; f < images.size(); ++f) {
    const ImageErrors e = compareFrame(images[f], reference[f]);
    sum.meanAbsError += e.meanAbsError, sum.rmse += e.rmse;
    sum.intensityErrorPct += e.intensityErrorPct;
    if (referenceDepth.empty()) continue;
    const std::vector<float>& z = referenceDepth[f];
    if (z.size() * 3 != reference[f].rgb.size())
      throw Error("trade: internal: reference depth of another size");
    std::vector<size_t> hits;
    for (size_t i = 0; i < z.size(); ++i)
      if (z[i] > 0.0f) hits.push_back(i);
    std::stable_sort(hits.begin(), hits.end(), [&](size_t i, size_t j) { return z[i] < z[j]; });
    // Change from the image to the reference, in percent of the reference: minus the error.
    frameChange(reference[f].rgb, images[f].rgb, hits, bandPct);
  }
  const double n = static_cast<double>(images.size());
  ImageErrors out{sum.meanAbsError / n, sum.rmse / n, sum.intensityErrorPct / n, 0.0};
  for (double pct : bandPct)
    if (std::abs(pct / n) > std::abs(out.worstBandPct)) out.worstBandPct = -pct / n;
  return out;
}

}  // namespace meso::trade
