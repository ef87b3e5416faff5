// Kautz et al. 2001, section 4: the NDF as a map over the normal's x and y components.
#include "meso/synthesis/tabulated_ndf.h"

#include "meso/core/error.h"
#include "meso/core/hash.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace meso {
namespace {

constexpr int kNormalizationGrid = 2048;

}  // namespace

TabulatedNdf::TabulatedNdf(int width, int height, std::vector<float> values)
    : width_(width), height_(height), values_(std::move(values)) {
  if (width < 2 || height < 2 ||
      values_.size() != static_cast<size_t>(width) * static_cast<size_t>(height)) {
    std::ostringstream s;
    s << "tabulated NDF: need a grid of at least 2x2 values with width * height entries (got "
      << width << "x" << height << " and " << values_.size() << " values)";
    throw Error(s.str());
  }
  for (size_t k = 0; k < values_.size(); ++k) {
    if (!(values_[k] >= 0.0f) || !std::isfinite(values_[k])) {
      std::ostringstream s;
      s << "tabulated NDF: value " << values_[k] << " at cell (" << k % width << ", " << k / width
        << ") is negative or not finite";
      throw Error(s.str());
    }
  }
  // The disk integral of the bilinear interpolant (the density of (m.x, m.y) is D itself).
  double sum = 0.0;
  const double h = 2.0 / kNormalizationGrid;
  for (int b = 0; b < kNormalizationGrid; ++b) {
    const double y = -1.0 + (b + 0.5) * h;
    for (int a = 0; a < kNormalizationGrid; ++a) {
      const double x = -1.0 + (a + 0.5) * h;
      if (x * x + y * y < 1.0) sum += interpolate(static_cast<float>(x), static_cast<float>(y));
    }
  }
  sum *= h * h;
  if (!(sum > 0.0) || !std::isfinite(sum))
    throw Error("tabulated NDF: the values are zero over the whole unit disk (no normal has mass)");
  const float scale = static_cast<float>(1.0 / sum);
  for (float& v : values_) v *= scale;

  int i0 = width, i1 = -1, j0 = height, j1 = -1;
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i)
      if (cell(i, j) > 0.0f)
        i0 = std::min(i0, i), i1 = std::max(i1, i), j0 = std::min(j0, j), j1 = std::max(j1, j);
  // Cell k covers [-1 + k * 2 / w, -1 + (k + 1) * 2 / w]; one more cell either side for the spill.
  const auto extent = [](int lo, int hi, int n) {
    const float a = -1.0f + (lo - 1) * 2.0f / n, b = -1.0f + (hi + 2) * 2.0f / n;
    return std::min(1.0f, std::max(std::abs(a), std::abs(b)));
  };
  support_ = Vec2(extent(i0, i1, width), extent(j0, j1, height));
}

float TabulatedNdf::interpolate(float x, float y) const {
  // Continuous cell coordinates: cell centre i sits at i + 0.5.
  const float fx = std::clamp((x + 1.0f) * 0.5f * width_ - 0.5f, 0.0f, width_ - 1.0f);
  const float fy = std::clamp((y + 1.0f) * 0.5f * height_ - 0.5f, 0.0f, height_ - 1.0f);
  const int i = std::min(static_cast<int>(fx), width_ - 2),
            j = std::min(static_cast<int>(fy), height_ - 2);
  const float tx = fx - i, ty = fy - j;
  const float* row0 = &values_[static_cast<size_t>(j) * width_ + i];
  const float* row1 = row0 + width_;
  const float a = row0[0] + tx * (row0[1] - row0[0]), b = row1[0] + tx * (row1[1] - row1[0]);
  return a + ty * (b - a);
}

float TabulatedNdf::D(const Vec3& m) const {
  if (!(m.z > 0.0f) || !std::isfinite(m.x) || !std::isfinite(m.y)) return 0.0f;
  return interpolate(m.x, m.y);
}

std::string TabulatedNdf::name() const {
  std::ostringstream s;
  s << "tabulated(" << width_ << "x" << height_ << ")";
  return s.str();
}

uint64_t TabulatedNdf::fingerprint() const {
  return Hasher()
      .string("TabulatedNdf/1")
      .value(width_)
      .value(height_)
      .bytes(values_.data(), values_.size() * sizeof(float))
      .digest();
}

}  // namespace meso
