// Becker & Max 1993, section 2.2: the height table ("bump map") B of a relief level.
#pragma once

#include "meso/core/image.h"
#include "meso/core/memory_budget.h"
#include "meso/relief/bump_derivatives.h"
#include "meso/relief/height_source.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace meso {

// How a table's highestFrequency() is found (docs/relief.md).
enum class FrequencyEstimate {
  Spectral,  // measured: power spectra of rows and columns (highest_frequency.h), default
  Nyquist,   // half the texel count along the longer-resolved axis: max(W, H) / 2
};

struct HeightTableOptions {
  bool periodic = true;  // wrap at the edges; false: clamp to the edge texels
  BumpDerivativeMethod method = BumpDerivativeMethod::Quadratic;
  FrequencyEstimate frequency = FrequencyEstimate::Spectral;
  float energyCutoff = 1e-3f;  // Spectral: fraction of the non-constant energy allowed above freq
  uint64_t memoryLimitBytes = defaultMemoryLimitBytes();  // loadHeightTable's image decoding
};

// The index and fraction of a texel coordinate along one axis, and the indices of the four texels
// floor(x) - 1 .. floor(x) + 2 after wrapping or clamping: the taps of every lookup.
struct TexelTaps {
  int k[4];
  float t;  // x - floor(x) rounded to float: in [0, 1] (1 only just below an integer)
};

// W x H texels; texel (i, j) is centred at tile coordinates ((i + 0.5) / W, (j + 0.5) / H), rows
// from the bottom (v grows upwards, image row 0 is the top). Heights are bilinear between centres;
// gradients come from the chosen BumpDerivativeMethod.
class HeightTable : public HeightSource {
 public:
  // texels: row-major, row j = 0 at v = 0. Throws meso::Error for a bad size or non-finite texels.
  HeightTable(int width, int height, std::vector<float> texels, HeightTableOptions options = {});
  HeightTable(int width, int height, std::vector<float> texels, bool periodic,
              BumpDerivativeMethod method = BumpDerivativeMethod::Quadratic);
  // One channel, or the Rec. 709 luminance 0.2126 R + 0.7152 G + 0.0722 B of RGB; the alpha of
  // grey + alpha or RGBA images is ignored (ignoredAlpha() says so; colour is read unassociated,
  // not multiplied by alpha). Throws meso::Error("FILE: ...") for zero size, more than 4
  // channels, NaN or infinite texels (naming the texel).
  HeightTable(const Image& image, const std::filesystem::path& file,
              HeightTableOptions options = {});
  static HeightTable fromImage(const Image& image, const std::filesystem::path& file,
                               bool periodic = true);
  static HeightTable load(const std::filesystem::path& file, bool periodic = true,
                          uint64_t memoryLimitBytes = defaultMemoryLimitBytes());

  float height(Vec2 p) const override;                       // bilinear
  Vec2 gradient(Vec2 p) const override;                      // per unit of tile coordinate
  float highestFrequency() const override { return freq_; }  // cycles per tile
  uint64_t fingerprint() const override;
  float maxAbsHeight() const override { return maxAbs_; }  // bilinear never leaves the texel range
  float meanHeight() const override { return mean_; }  // texel mean (a periodic bilinear's mean)
  int texelsPerSide() const override { return std::max(width_, height_); }

  // The image it was read from had an alpha channel, which the heights ignore.
  bool ignoredAlpha() const { return ignoredAlpha_; }
  int width() const { return width_; }
  int heightTexels() const { return height_; }
  bool periodic() const { return options_.periodic; }
  const HeightTableOptions& options() const { return options_; }
  BumpDerivativeMethod method() const { return options_.method; }
  void setMethod(BumpDerivativeMethod m) { options_.method = m; }
  const std::vector<float>& texels() const { return texels_; }

  // Texel (i, j) for any integers (wrapped or clamped), and for indices already in range.
  float texel(int i, int j) const;
  float at(int i, int j) const { return texels_[static_cast<size_t>(j) * width_ + i]; }
  // Taps along x (columns) and y (rows) at texel coordinates x = u W - 0.5, y = v H - 0.5.
  TexelTaps tapsX(double x) const { return tapsAlong(x, width_, inverseWidth_, options_.periodic); }
  TexelTaps tapsY(double y) const {
    return tapsAlong(y, height_, inverseHeight_, options_.periodic);
  }
  // Bilinear height at texel coordinates.
  float bilinear(double x, double y) const;

 private:
  static TexelTaps tapsAlong(double x, int n, double inverseN, bool periodic);
  int width_, height_;
  double inverseWidth_, inverseHeight_;
  std::vector<float> texels_;
  HeightTableOptions options_;
  float freq_ = 1.0f;
  float maxAbs_ = 0.0f;
  float mean_ = 0.0f;
  bool ignoredAlpha_ = false;
};

// floor(x) for |x| < 2^62 without a libm call (x86-64 without SSE4.1 has no inline floor).
inline double floorFast(double x) {
  const double t = static_cast<double>(static_cast<int64_t>(x));
  return t > x ? t - 1.0 : t;
}

// Inline: this is the addressing of every per-sample lookup.
inline TexelTaps HeightTable::tapsAlong(double x, int n, double inverseN, bool periodic) {
  if (!(std::abs(x) < 1e15)) x = 0.0;  // NaN and huge coordinates: any finite answer will do
  if (periodic)
    x -= n * floorFast(x * inverseN);
  else
    x = std::clamp(x, -2.0, n + 1.0);  // beyond this every tap is an edge texel anyway
  const double f = floorFast(x);
  TexelTaps taps;
  taps.t = static_cast<float>(x - f);
  int i = static_cast<int>(f);
  if (periodic) {
    if (i >= n) i -= n;  // x - n floor(x / n) can round up to n
    if (n >= 2) {        // i in [0, n): the taps i - 1 .. i + 2 need at most one fold each
      for (int m = 0; m < 4; ++m) {
        const int a = i - 1 + m;
        taps.k[m] = a < 0 ? a + n : (a >= n ? a - n : a);
      }
    } else {
      taps.k[0] = taps.k[1] = taps.k[2] = taps.k[3] = 0;
    }
  } else {
    for (int m = 0; m < 4; ++m) taps.k[m] = std::clamp(i - 1 + m, 0, n - 1);
  }
  return taps;
}

// readImage(file, options.memoryLimitBytes) and the checks of the Image constructor. Throws
// meso::Error("FILE: ...") for a missing, unreadable, truncated, zero-size or wrongly-channelled
// file.
HeightTable loadHeightTable(const std::filesystem::path& file, HeightTableOptions options = {});

}  // namespace meso
