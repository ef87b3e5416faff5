// Kautz et al. 2001, section 4: x_n = M^-1(r1), y_n = C^-1(r2 | x_n) over the normal's x and y,
// tabulated as L(r1, r2); section 7: its inverse for index textures.
#include "meso/synthesis/normal_lookup_table.h"

#include "meso/core/error.h"
#include "meso/core/piecewise_cdf.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <span>
#include <string>

namespace meso {
namespace {

// x^(1/3) for x in [0, 1/8] to float precision, without std::cbrt's ~25 ns: a bit-level first
// guess of x^(-1/3) (exponent / -3), division-free Newton steps y <- y (4 - x y^3) / 3, then
// x y^2.
inline float cubeRoot(float x) {
  if (!(x > 1e-30f)) return 0.0f;
  float y = std::bit_cast<float>(0x54a2fa8cu - std::bit_cast<uint32_t>(x) / 3u);
  for (int k = 0; k < 4; ++k) y *= (4.0f - x * y * y * y) * (1.0f / 3.0f);
  return x * y * y;
}

}  // namespace

float NormalLookupTable::unwarp(float r) {
  r = std::clamp(r, 0.0f, 1.0f);
  return r < 0.5f ? cubeRoot(0.25f * r) : 1.0f - cubeRoot(0.25f * (1.0f - r));
}

NormalLookupTable::NormalLookupTable(const Ndf& ndf, const NormalLookupOptions& options)
    : res_(options.resolution), pdfRes_(options.pdfResolution), support_(ndf.support()) {
  if (res_ < 2 || res_ > 8192 || pdfRes_ < 1 || pdfRes_ > 8192 || options.subsamples < 1 ||
      options.subsamples > 64)
    throw Error(
        "normal lookup table: need 2..8192 nodes, 1..8192 density cells and 1..64 subsamples "
        "(got " +
        std::to_string(res_) + ", " + std::to_string(pdfRes_) + ", " +
        std::to_string(options.subsamples) + ")");
  const int n = pdfRes_, k = options.subsamples;
  const double wx = 2.0 * support_.x / n, wy = 2.0 * support_.y / n;
  // Cell masses of the disk density D (their common factor wx wy / k^2 cancels in the CDFs).
  std::vector<double> mass(static_cast<size_t>(n) * n, 0.0), column(n, 0.0);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      double m = 0.0;
      for (int a = 0; a < k; ++a) {
        const double x = -support_.x + (i + (a + 0.5) / k) * wx;
        for (int b = 0; b < k; ++b) {
          const double y = -support_.y + (j + (b + 0.5) / k) * wy, r2 = x * x + y * y;
          if (r2 < 1.0)
            m += ndf.D(Vec3(static_cast<float>(x), static_cast<float>(y),
                            static_cast<float>(std::sqrt(1.0 - r2))));
        }
      }
      mass[static_cast<size_t>(i) * n + j] = m;
      column[i] += m;
    }
  }
  double total = 0.0;
  for (double m : column) total += m;
  if (!(total > 0.0) || !std::isfinite(total))
    throw Error("normal lookup table: the NDF " + ndf.name() +
                " has no mass inside its support box");
  appendCumulative(std::span<const double>(column), marginalCdf_);
  conditionalCdf_.reserve(static_cast<size_t>(n) * (n + 1));
  for (int i = 0; i < n; ++i)
    appendCumulative(std::span<const double>(&mass[static_cast<size_t>(i) * n], n),
                     conditionalCdf_);

  nodes_.resize(static_cast<size_t>(res_) * res_);
  for (int i = 0; i < res_; ++i) {
    int c = 0;
    const float x = marginalInverse(warp(static_cast<float>(i) / (res_ - 1)), c);
    for (int j = 0; j < res_; ++j) {
      const float y = conditionalInverse(c, warp(static_cast<float>(j) / (res_ - 1)));
      nodes_[static_cast<size_t>(j) * res_ + i] = Vec2(x, y);
    }
  }
}

CdfRows NormalLookupTable::conditional(int column) const {
  const size_t edges = static_cast<size_t>(pdfRes_) + 1;
  return CdfRows(
      std::span<const float>(&conditionalCdf_[static_cast<size_t>(column) * edges], edges));
}

// The inverses land inside the support of their CDF, so the column of x has mass: r >= 1 lands on
// the right edge of the last cell with mass, r <= 0 on the left edge of the first.
float NormalLookupTable::marginalInverse(float r1, int& column) const {
  const BinPosition pos = cdfInverseInBins(CdfRows(marginalCdf_), r1, InverseSide::Upper);
  column = static_cast<int>(pos.bin);
  return -support_.x + pos.t() * (2.0f * support_.x / pdfRes_);
}

float NormalLookupTable::conditionalInverse(int column, float r2) const {
  const BinPosition pos = cdfInverseInBins(conditional(column), r2, InverseSide::Upper);
  return -support_.y + pos.t() * (2.0f * support_.y / pdfRes_);
}

Vec3 NormalLookupTable::sampleExact(Vec2 r) const {
  int c = 0;
  const float x = marginalInverse(std::clamp(r.x, 0.0f, 1.0f), c);
  return normalFromXY(Vec2(x, conditionalInverse(c, std::clamp(r.y, 0.0f, 1.0f))));
}

Vec2 NormalLookupTable::cdf(const Vec3& m) const {
  const float px = std::clamp((m.x + support_.x) / (2.0f * support_.x) * pdfRes_, 0.0f,
                              static_cast<float>(pdfRes_));
  const float py = std::clamp((m.y + support_.y) / (2.0f * support_.y) * pdfRes_, 0.0f,
                              static_cast<float>(pdfRes_));
  const int c = std::min(static_cast<int>(px), pdfRes_ - 1);
  return Vec2(cdfForwardInBins(CdfRows(marginalCdf_), px), cdfForwardInBins(conditional(c), py));
}

Vec2 NormalLookupTable::interpolate(Vec2 t) const {
  const int i = std::min(static_cast<int>(t.x), res_ - 2),
            j = std::min(static_cast<int>(t.y), res_ - 2);
  const float a = t.x - i, b = t.y - j;
  const Vec2* row0 = &nodes_[static_cast<size_t>(j) * res_ + i];
  const Vec2* row1 = row0 + res_;
  const Vec2 p = row0[0] + a * (row0[1] - row0[0]), q = row1[0] + a * (row1[1] - row1[0]);
  return p + b * (q - p);
}

Vec3 NormalLookupTable::lookup(Vec2 r) const {
  const float s = static_cast<float>(res_ - 1);
  return normalFromXY(interpolate(Vec2(unwarp(r.x) * s, unwarp(r.y) * s)));
}

Vec2 NormalLookupTable::invert(const Vec3& m) const {
  // First coordinate: node x depends on i only and rises with i.
  const float tx = inverseNondecreasing([&](int i) { return nodes_[i].x; }, res_, m.x);
  // Second coordinate: y along the column blended at tx rises with j.
  const int i = std::min(static_cast<int>(tx), res_ - 2);
  const float a = tx - i;
  const auto yAt = [&](int j) {
    const Vec2* row = &nodes_[static_cast<size_t>(j) * res_ + i];
    return row[0].y + a * (row[1].y - row[0].y);
  };
  const float ty = inverseNondecreasing(yAt, res_, m.y);
  const float s = static_cast<float>(res_ - 1);
  return Vec2(warp(tx / s), warp(ty / s));
}

float NormalLookupTable::cellAngle(Vec2 r) const {
  const float s = static_cast<float>(res_ - 1);
  const int i = std::min(static_cast<int>(unwarp(r.x) * s), res_ - 2);
  const int j = std::min(static_cast<int>(unwarp(r.y) * s), res_ - 2);
  const Vec3 c[4] = {normalFromXY(nodeXY(i, j)), normalFromXY(nodeXY(i + 1, j)),
                     normalFromXY(nodeXY(i, j + 1)), normalFromXY(nodeXY(i + 1, j + 1))};
  float largest = 0.0f;
  for (int p = 0; p < 4; ++p)
    for (int q = p + 1; q < 4; ++q)
      largest = std::max(largest, std::acos(std::clamp(glm::dot(c[p], c[q]), -1.0f, 1.0f)));
  return largest;
}

}  // namespace meso
