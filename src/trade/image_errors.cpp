// Image error against the reference (see image_errors.h).
#include "meso/trade/image_errors.h"

#include "meso/core/error.h"

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

ImageErrors compareFrames(const std::vector<RgbImage>& images,
                          const std::vector<RgbImage>& reference) {
  if (images.size() != reference.size() || images.empty())
    throw Error("trade: internal: comparing different numbers of frames");
  ImageErrors sum;
  for (size_t f = 0; f < images.size(); ++f) {
    const ImageErrors e = compareFrame(images[f], reference[f]);
    sum.meanAbsError += e.meanAbsError, sum.rmse += e.rmse;
    sum.intensityErrorPct += e.intensityErrorPct;
  }
  const double n = static_cast<double>(images.size());
  return {sum.meanAbsError / n, sum.rmse / n, sum.intensityErrorPct / n};
}

}  // namespace meso::trade
