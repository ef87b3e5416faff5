// Kautz et al. 2001, section 4: an NDF stored as a 2D map over the x and y components of the
// normal (their Figure 2, right), e.g. measured or estimated from a relief (section 7).
#pragma once

#include "meso/synthesis/ndf.h"

#include <vector>

namespace meso {

// values[j * width + i] is D (up to a scale) at the cell centre
//   (m.x, m.y) = (-1 + (i + 0.5) * 2 / width, -1 + (j + 0.5) * 2 / height).
// D(m) is the bilinear interpolation of the cell centres at (m.x, m.y) (clamped to the edge cells),
// 0 for m.z <= 0, times the scale that makes integral D cos dw = 1 (the disk integral of D, done
// at construction on a 2048^2 midpoint grid). Cells outside the unit disk only shape the
// interpolation next to the rim.
class TabulatedNdf : public Ndf {
 public:
  // meso::Error when width or height < 2, values.size() != width * height, a value is negative,
  // NaN or Inf, or D is zero over the whole disk.
  TabulatedNdf(int width, int height, std::vector<float> values);

  float D(const Vec3& m) const override;
  // The bounding box of the non-zero cells, one cell wider (the bilinear spill), capped at 1.
  Vec2 support() const override { return support_; }
  std::string name() const override;
  uint64_t fingerprint() const override;

  int width() const { return width_; }
  int height() const { return height_; }
  // The stored values times the normalization scale: D at the cell centres.
  float cell(int i, int j) const { return values_[static_cast<size_t>(j) * width_ + i]; }

 private:
  float interpolate(float x, float y) const;  // bilinear, unnormalized grid coordinates
  int width_, height_;
  std::vector<float> values_;
  Vec2 support_{1.0f};
};

}  // namespace meso
