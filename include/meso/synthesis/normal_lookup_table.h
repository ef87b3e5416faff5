// Kautz et al. 2001, section 4: the lookup table L(r1, r2) that maps two uniform numbers to a
// microfacet normal distributed by the NDF, through the marginal M(x) and conditional C(y | x)
// inverse CDFs over the normal's x and y components (their "2D hemispherical map").
#pragma once

#include "meso/core/math.h"
#include "meso/core/piecewise_cdf.h"
#include "meso/synthesis/ndf.h"

#include <vector>

namespace meso {

struct NormalLookupOptions {
  int resolution = 256;     // L's nodes per axis (the paper's 256 x 256)
  int pdfResolution = 256;  // cells per axis of the piecewise-constant density over the support box
  int subsamples = 4;       // midpoint samples per cell axis when D is integrated over a cell
};

// The density of (m.x, m.y) over the unit disk is D(m) itself (dA = cos(theta) dw), so the table
// samples D restricted to the NDF's support box [-sx, sx] x [-sy, sy]:
//  1. cell masses of D on a pdfResolution^2 grid (D integrated with subsamples^2 midpoints);
//  2. x = M^-1(r1) from the column marginal, y = C^-1(r2 | column of x): both exact inverses of
//     the piecewise-constant density (linear inside a cell);
//  3. L stores (x, y) at nodes (i, j) placed at r = warp(i / (res - 1)), where warp(t) = 4 t^3 for
//     t < 1/2 and 1 - 4 (1 - t)^3 above (C1): nodes crowd towards r = 0 and 1, where the inverse
//     CDFs run off into the tails, so the first and last cells hold 2.4e-7 of the mass rather than
//     1/255 (which bilinear interpolation would smear evenly over the far tail).
//  lookup() interpolates (x, y) bilinearly in the warped coordinates and returns
//  normalFromXY(x, y) = (x, y, sqrt(1 - x^2 - y^2)).
// The normals are in the NDF's frame: an anisotropic NDF's x axis is its principal axis, and the
// caller maps them to the surface through the surface tangent (see synthesized_shading.h).
// Immutable after construction; lookup() and invert() are allocation-free and thread-safe.
class NormalLookupTable {
 public:
  explicit NormalLookupTable(const Ndf& ndf, const NormalLookupOptions& options = {});

  // L(r1, r2): a unit microfacet normal (z >= 0); r is clamped to [0, 1]^2.
  Vec3 lookup(Vec2 r) const;
  // The exact inverse-CDF sample of the piecewise-constant density (no node interpolation): what
  // L approximates. A unit normal.
  Vec3 sampleExact(Vec2 r) const;
  // (M(x), C(y | x)): the forward CDFs at m's (x, y), clamped into the support box. The inverse of
  // sampleExact().
  Vec2 cdf(const Vec3& m) const;
  // r with lookup(r) = m: the exact inverse of the bilinear table (Kautz et al. section 7's index
  // texture). Node x depends on i alone, so x fixes the table's first coordinate (a monotone
  // search), and then y fixes the second along the blended column (another). m.x, m.y outside
  // what the table reaches (beyond the support box or in zero-density gaps) clamp to the nearest
  // node value per axis. Allocation-free.
  Vec2 invert(const Vec3& m) const;
  // The largest angle (radians) between the four nodes of the table cell that r falls in: how far
  // apart two normals one table cell apart can be.
  float cellAngle(Vec2 r) const;

  int resolution() const { return res_; }
  Vec2 support() const { return support_; }
  // The node placement and its inverse (see above); both map [0, 1] onto itself.
  static float warp(float t) {
    return t < 0.5f ? 4.0f * t * t * t : 1.0f - 4.0f * (1.0f - t) * (1.0f - t) * (1.0f - t);
  }
  static float unwarp(float r);

 private:
  float marginalInverse(float r1, int& column) const;
  float conditionalInverse(int column, float r2) const;
  CdfRows conditional(int column) const;  // C(y | column)
  Vec2 nodeXY(int i, int j) const { return nodes_[static_cast<size_t>(j) * res_ + i]; }
  // Bilinear (x, y) at table coordinates t in [0, res - 1]^2.
  Vec2 interpolate(Vec2 t) const;

  int res_, pdfRes_;
  Vec2 support_;
  std::vector<float> marginalCdf_;     // pdfRes + 1 edges
  std::vector<float> conditionalCdf_;  // pdfRes columns of pdfRes + 1 edges
  std::vector<Vec2> nodes_;            // res^2 (x, y) pairs, row j = r2 node
};

// The unit vector (x, y, sqrt(1 - x^2 - y^2)). Points beyond the rim (a density cell that straddles
// the unit circle is sampled uniformly, and bilinear interpolation can stray) are pulled radially
// to r^2 = 1 - 1e-6, so the normal never lies in the tangent plane.
inline Vec3 normalFromXY(Vec2 xy) {
  constexpr float kRim2 = 1.0f - 1e-6f;
  float r2 = xy.x * xy.x + xy.y * xy.y;
  if (r2 > kRim2) {
    xy *= std::sqrt(kRim2 / r2);
    r2 = kRim2;
  }
  return Vec3(xy.x, xy.y, std::sqrt(1.0f - r2));
}

}  // namespace meso
