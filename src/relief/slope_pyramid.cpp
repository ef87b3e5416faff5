// Schilling, "Antialiasing of Bump Maps": the recursive rule of the roughness pyramid,
// K_l = 1/4 sum_n K_{l-1,n} + 1/4 sum_n (f_n - f)(f_n - f)^T over the 2 x 2 children n.
#include "meso/relief/slope_pyramid.h"

#include "meso/core/error.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace meso {
namespace {

bool isPowerOfTwo(int n) { return n > 0 && (n & (n - 1)) == 0; }
int nextPowerOfTwo(int n) {
  int p = 1;
  while (p < n && p < (1 << 30)) p <<= 1;
  return p;
}

// Mean slope and covariance, in double while the pyramid is built.
struct Moments {
  double fu = 0.0, fv = 0.0, a = 0.0, b = 0.0, c = 0.0;
};

// One level up: each texel averages its (up to) 2 x 2 children and adds their spread.
std::vector<Moments> reduce(const std::vector<Moments>& child, int cw, int ch, int w, int h) {
  std::vector<Moments> out(static_cast<size_t>(w) * h);
  const int nx = cw > w ? 2 : 1, ny = ch > h ? 2 : 1;
  const double inv = 1.0 / (nx * ny);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      Moments m;
      for (int y = 0; y < ny; ++y)
        for (int x = 0; x < nx; ++x) {
          const Moments& k = child[static_cast<size_t>(j * ny + y) * cw + (i * nx + x)];
          m.fu += inv * k.fu;
          m.fv += inv * k.fv;
          m.a += inv * k.a;
          m.b += inv * k.b;
          m.c += inv * k.c;
        }
      for (int y = 0; y < ny; ++y)
        for (int x = 0; x < nx; ++x) {
          const Moments& k = child[static_cast<size_t>(j * ny + y) * cw + (i * nx + x)];
          const double du = k.fu - m.fu, dv = k.fv - m.fv;
          m.a += inv * du * du;
          m.b += inv * du * dv;
          m.c += inv * dv * dv;
        }
      out[static_cast<size_t>(j) * w + i] = m;
    }
  return out;
}

// Wrapped or clamped index and weight of the two bilinear taps along one axis.
inline void taps2(double x, int n, double inverseN, bool periodic, int& i0, int& i1, float& t) {
  if (!(std::abs(x) < 1e15)) x = 0.0;
  if (periodic)
    x -= n * floorFast(x * inverseN);
  else
    x = std::clamp(x, -1.0, static_cast<double>(n));
  const double f = floorFast(x);
  t = static_cast<float>(x - f);
  i0 = static_cast<int>(f);
  if (periodic) {
    if (i0 >= n) i0 -= n;
    if (i0 < 0) i0 += n;  // x * inverseN rounded up to an integer: x is a hair below 0
    i1 = i0 + 1 >= n ? 0 : i0 + 1;
  } else {
    i1 = std::clamp(i0 + 1, 0, n - 1);
    i0 = std::clamp(i0, 0, n - 1);
  }
}

}  // namespace

SlopePyramid::SlopePyramid(const HeightSource& source, int width, int height, bool periodic)
    : periodic_(periodic) {
  if (!isPowerOfTwo(width) || !isPowerOfTwo(height) || width > (1 << 14) || height > (1 << 14))
    throw Error("slope pyramid: width and height must be powers of two up to 16384, got " +
                std::to_string(width) + "x" + std::to_string(height));
  std::vector<Vec2> finest(static_cast<size_t>(width) * height);
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      const Vec2 p((static_cast<float>(i) + 0.5f) / static_cast<float>(width),
                   (static_cast<float>(j) + 0.5f) / static_cast<float>(height));
      finest[static_cast<size_t>(j) * width + i] = source.gradient(p);
    }
  build(finest, width, height);
}

SlopePyramid::SlopePyramid(const HeightTable& table)
    : SlopePyramid(table, nextPowerOfTwo(table.width()), nextPowerOfTwo(table.heightTexels()),
                   table.periodic()) {}

void SlopePyramid::build(const std::vector<Vec2>& finest, int width, int height) {
  std::vector<Moments> m(finest.size());
  for (size_t k = 0; k < finest.size(); ++k) m[k].fu = finest[k].x, m[k].fv = finest[k].y;
  int w = width, h = height;
  for (;;) {
    Level level{w, h, 1.0 / w, 1.0 / h, std::vector<Texel>(m.size())};
    for (size_t k = 0; k < m.size(); ++k) {
      const RoughnessFactor D = roughnessFactor(
          {static_cast<float>(m[k].a), static_cast<float>(m[k].b), static_cast<float>(m[k].c)});
      level.texels[k] = {static_cast<float>(m[k].fu), static_cast<float>(m[k].fv), D.d1, D.d2,
                         D.d3};
    }
    levels_.push_back(std::move(level));
    if (w == 1 && h == 1) break;
    const int nw = std::max(1, w / 2), nh = std::max(1, h / 2);
    m = reduce(m, w, h, nw, nh);
    w = nw, h = nh;
  }
}

const SlopePyramid::Texel& SlopePyramid::texel(int level, int i, int j) const {
  const Level& L = levels_[level];
  const auto fold = [&](int a, int n) {
    if (!periodic_) return std::clamp(a, 0, n - 1);
    const int r = a % n;
    return r < 0 ? r + n : r;
  };
  return L.texels[static_cast<size_t>(fold(j, L.height)) * L.width + fold(i, L.width)];
}

Vec2 SlopePyramid::slope(int level, int i, int j) const {
  const Texel& t = texel(level, i, j);
  return {t.fu, t.fv};
}

RoughnessFactor SlopePyramid::roughness(int level, int i, int j) const {
  const Texel& t = texel(level, i, j);
  return {t.d1, t.d2, t.d3};
}

void SlopePyramid::bilinear(int level, Vec2 p, Vec2& mean, SlopeCovariance& K) const {
  const Level& L = levels_[level];
  int i0, i1, j0, j1;
  float tx, ty;
  taps2(static_cast<double>(p.x) * L.width - 0.5, L.width, L.inverseWidth, periodic_, i0, i1, tx);
  taps2(static_cast<double>(p.y) * L.height - 0.5, L.height, L.inverseHeight, periodic_, j0, j1,
        ty);
  const int is[2] = {i0, i1}, js[2] = {j0, j1};
  const float wx[2] = {1.0f - tx, tx}, wy[2] = {1.0f - ty, ty};
  mean = Vec2(0.0f);
  K = {};
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x) {
      const Texel& t = L.texels[static_cast<size_t>(js[y]) * L.width + is[x]];
      const float w = wx[x] * wy[y];
      mean += w * Vec2(t.fu, t.fv);
      K += w * covarianceOf({t.d1, t.d2, t.d3});
    }
}

SlopeSample SlopePyramid::lookupLevel(Vec2 p, float lod) const {
  const float top = static_cast<float>(levels() - 1);
  lod = std::isnan(lod) ? 0.0f : std::clamp(lod, 0.0f, top);
  const int l0 = std::min(static_cast<int>(lod), levels() - 1);
  const float t = lod - static_cast<float>(l0);
  SlopeSample s;
  s.lod = lod;
  bilinear(l0, p, s.mean, s.roughness);
  if (t > 0.0f && l0 + 1 < levels()) {
    Vec2 mean;
    SlopeCovariance K;
    bilinear(l0 + 1, p, mean, K);
    s.mean = (1.0f - t) * s.mean + t * mean;
    s.roughness = (1.0f - t) * s.roughness + t * K;
  }
  return s;
}

SlopeSample SlopePyramid::lookup(Vec2 p, Vec2 dx, Vec2 dy) const {
  const float width = std::max(glm::length(dx), glm::length(dy));  // texels of level 0
  return lookupLevel(p, width > 1.0f ? std::log2(width) : 0.0f);   // NaN: level 0
}

}  // namespace meso
