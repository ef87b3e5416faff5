// Image error and local contrast against the reference (see image_errors.h).
#include "meso/trade/image_errors.h"

#include "meso/core/error.h"
#include "meso/render/local_contrast.h"

#include <algorithm>
#include <cmath>
#include <limits>

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
  return {
      .meanAbsError = n > 0.0 ? absSum / n : 0.0,
      .rmse = n > 0.0 ? std::sqrt(squares / n) : 0.0,
      .intensityErrorPct = mr > 0.0 ? 100.0 * std::abs(mi - mr) / mr : (mi == mr ? 0.0 : 100.0)};
}

// The frame's luminance, and its second seed's when there is one.
LuminanceImage luminanceOf(const RgbImage& image, const std::vector<RgbImage>& second, size_t f) {
  LuminanceImage out{.width = image.width, .height = image.height, .y = {}, .ySecond = {}};
  const auto lum = [](const RgbImage& im) {
    std::vector<float> y(im.rgb.size() / 3);
    for (size_t i = 0; i < y.size(); ++i)
      y[i] = static_cast<float>(luminance(im.rgb[3 * i], im.rgb[3 * i + 1], im.rgb[3 * i + 2]));
    return y;
  };
  out.y = lum(image);
  if (!second.empty()) {
    if (second.size() <= f || second[f].rgb.size() != image.rgb.size())
      throw Error("trade: internal: a second-seed frame of another size");
    out.ySecond = lum(second[f]);
  }
  return out;
}

// Per pixel the depth band of `hits` (sorted near to far, kDepthBands equal counts), -1 elsewhere.
std::vector<int> depthBandLabels(const std::vector<size_t>& hits, size_t pixels) {
  std::vector<int> label(pixels, -1);
  for (int band = 0; band < kDepthBands; ++band)
    for (size_t k = hits.size() * band / kDepthBands; k < hits.size() * (band + 1) / kDepthBands;
         ++k)
      label[hits[k]] = band;
  return label;
}

// The ratio furthest from 1 over the bands where the reference shows relief, NaN if none does.
double worstRatio(const std::vector<ContrastSums>& image, const std::vector<ContrastSums>& ref) {
  double worst = std::numeric_limits<double>::quiet_NaN();
  for (size_t b = 0; b < ref.size(); ++b) {
    const double r = contrastRatio(image[b], ref[b]);
    if (!std::isnan(r) && (std::isnan(worst) || std::abs(r - 1.0) > std::abs(worst - 1.0)))
      worst = r;
  }
  return worst;
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
                          const std::vector<std::vector<float>>& referenceDepth,
                          const std::vector<RgbImage>& imagesSecond,
                          const std::vector<RgbImage>& referenceSecond) {
  if (images.size() != reference.size() || images.empty())
    throw Error("trade: internal: comparing different numbers of frames");
  if (!referenceDepth.empty() && referenceDepth.size() != reference.size())
    throw Error("trade: internal: reference depth for a different number of frames");
  ImageErrors sum;
  std::vector<double> bandPct(kDepthBands, 0.0);
  std::vector<ContrastSums> imageDetail(kDepthBands), referenceDetail(kDepthBands);
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
    const std::vector<int> label = depthBandLabels(hits, z.size());
    addContrastBlocks(luminanceOf(images[f], imagesSecond, f), label, imageDetail);
    addContrastBlocks(luminanceOf(reference[f], referenceSecond, f), label, referenceDetail);
  }
  const double n = static_cast<double>(images.size());
  ImageErrors out{sum.meanAbsError / n, sum.rmse / n, sum.intensityErrorPct / n, 0.0,
                  worstRatio(imageDetail, referenceDetail)};
  for (double pct : bandPct)
    if (std::abs(pct / n) > std::abs(out.worstBandPct)) out.worstBandPct = -pct / n;
  return out;
}

ImageErrors compareRenders(const MeasuredRender& image, const MeasuredRender& reference) {
  return compareFrames(image.beauty, reference.beauty, reference.depth, image.secondBeauty,
                       reference.secondBeauty);
}

}  // namespace meso::trade
