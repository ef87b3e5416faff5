// Becker & Max 1993, section 2.2: height tables B, texel centres at ((i + .5) / W, (j + .5) / H).
#include "meso/relief/height_table.h"

#include "meso/core/error.h"
#include "meso/core/hash.h"
#include "meso/core/image_io.h"
#include "meso/relief/highest_frequency.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace meso {
namespace {

void checkTexels(int width, int height, const std::vector<float>& texels) {
  if (width <= 0 || height <= 0 || texels.size() != static_cast<size_t>(width) * height)
    throw Error("height table: expected " + std::to_string(width) + " x " + std::to_string(height) +
                " texels, got " + std::to_string(texels.size()) + " values");
}

float estimateFrequency(const std::vector<float>& texels, int width, int height,
                        const HeightTableOptions& o) {
  if (o.frequency == FrequencyEstimate::Nyquist)
    return 0.5f * static_cast<float>(std::max(width, height));
  const Vec2 f = highestFrequencies(texels.data(), width, height, o.periodic, o.energyCutoff);
  // A flat table has no detail; one cycle per tile keeps the level's wavelength finite.
  return std::max(1.0f, std::max(f.x, f.y));
}

// A second (of two) or fourth (of four) channel is alpha, which heights ignore.
bool hasAlpha(const Image& image) { return image.numChannels() == 2 || image.numChannels() == 4; }

// Image rows go top to bottom; table rows go bottom to top (v grows upwards).
std::vector<float> heightsOf(const Image& image, const std::filesystem::path& file) {
  const std::string name = file.string();
  if (image.width <= 0 || image.height <= 0)
    throw Error(name + ": height image has zero size (" + std::to_string(image.width) + "x" +
                std::to_string(image.height) + ")");
  const int c = image.numChannels();
  if (c < 1 || c > 4)
    throw Error(name + ": height image has " + std::to_string(c) +
                " channels; expected 1 (height), 2 (height and alpha), 3 (RGB) or 4 (RGBA), "
                "whose luminance is used");
  if (image.pixels.size() != static_cast<size_t>(image.width) * image.height * c)
    throw Error(name + ": height image has " + std::to_string(image.pixels.size()) +
                " values for " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                "x" + std::to_string(c));
  std::vector<float> texels(static_cast<size_t>(image.width) * image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const float v = c <= 2 ? image.at(x, y, 0)
                             : 0.2126f * image.at(x, y, 0) + 0.7152f * image.at(x, y, 1) +
                                   0.0722f * image.at(x, y, 2);
      if (!std::isfinite(v))
        throw Error(name + ": height image has a NaN or infinite texel at (" + std::to_string(x) +
                    ", " + std::to_string(y) + ")");
      texels[static_cast<size_t>(image.height - 1 - y) * image.width + x] = v;
    }
  return texels;
}

}  // namespace

HeightTable::HeightTable(int width, int height, std::vector<float> texels,
                         HeightTableOptions options)
    : width_(width),
      height_(height),
      inverseWidth_(width > 0 ? 1.0 / width : 0.0),
      inverseHeight_(height > 0 ? 1.0 / height : 0.0),
      texels_(std::move(texels)),
      options_(options) {
  checkTexels(width_, height_, texels_);
  for (size_t k = 0; k < texels_.size(); ++k)
    if (!std::isfinite(texels_[k]))
      throw Error("height table: texel " + std::to_string(k) + " is NaN or infinite");
  freq_ = estimateFrequency(texels_, width_, height_, options_);
  double sum = 0.0;
  for (float t : texels_) {
    maxAbs_ = std::max(maxAbs_, std::abs(t));
    sum += t;
  }
  mean_ = static_cast<float>(sum / static_cast<double>(texels_.size()));
}

HeightTable::HeightTable(int width, int height, std::vector<float> texels, bool periodic,
                         BumpDerivativeMethod method)
    : HeightTable(width, height, std::move(texels), HeightTableOptions{periodic, method}) {}

HeightTable::HeightTable(const Image& image, const std::filesystem::path& file,
                         HeightTableOptions options)
    : HeightTable(image.width, image.height, heightsOf(image, file), options) {
  ignoredAlpha_ = hasAlpha(image);
}

HeightTable HeightTable::fromImage(const Image& image, const std::filesystem::path& file,
                                   bool periodic) {
  return HeightTable(image, file, HeightTableOptions{periodic});
}

HeightTable HeightTable::load(const std::filesystem::path& file, bool periodic,
                              uint64_t memoryLimitBytes) {
  return loadHeightTable(file, {.periodic = periodic, .memoryLimitBytes = memoryLimitBytes});
}

HeightTable loadHeightTable(const std::filesystem::path& file, HeightTableOptions options) {
  return HeightTable(readImage(file, options.memoryLimitBytes), file, options);
}

float HeightTable::texel(int i, int j) const {
  const auto fold = [&](int a, int n) {
    if (!options_.periodic) return std::clamp(a, 0, n - 1);
    const int m = a % n;
    return m < 0 ? m + n : m;
  };
  return at(fold(i, width_), fold(j, height_));
}

float HeightTable::bilinear(double x, double y) const {
  const TexelTaps tx = tapsX(x), ty = tapsY(y);
  const auto row = [&](int j) { return (1.0f - tx.t) * at(tx.k[1], j) + tx.t * at(tx.k[2], j); };
  return (1.0f - ty.t) * row(ty.k[1]) + ty.t * row(ty.k[2]);
}

float HeightTable::height(Vec2 p) const {
  return bilinear(static_cast<double>(p.x) * width_ - 0.5,
                  static_cast<double>(p.y) * height_ - 0.5);
}

Vec2 HeightTable::gradient(Vec2 p) const {
  const Vec2 perTexel = bumpDerivatives(*this, static_cast<double>(p.x) * width_ - 0.5,
                                        static_cast<double>(p.y) * height_ - 0.5, options_.method);
  return {perTexel.x * static_cast<float>(width_), perTexel.y * static_cast<float>(height_)};
}

uint64_t HeightTable::fingerprint() const {
  return Hasher()
      .string("HeightTable")
      .value(width_)
      .value(height_)
      .value(options_.periodic)
      .value(options_.method)
      .bytes(texels_.data(), texels_.size() * sizeof(float))
      .digest();
}

}  // namespace meso
