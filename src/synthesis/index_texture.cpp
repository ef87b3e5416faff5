// Kautz et al. 2001, section 7: r1 = G(M(n_x)), r2 = G(C(n_y | n_x)) for an existing bump map,
// plus noise when zooming closer.
#include "meso/synthesis/index_texture.h"

#include "meso/core/error.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace meso {

IndexTexture::IndexTexture(const HeightSource& source, const NormalLookupTable& table,
                           int resolution, float slopeScale)
    : res_(resolution) {
  if (resolution < 1 || resolution > 16384 || !std::isfinite(slopeScale))
    throw Error("index texture: need 1..16384 texels per axis and a finite slope scale (got " +
                std::to_string(resolution) + ", " + std::to_string(slopeScale) + ")");
  const size_t n = static_cast<size_t>(res_) * res_;
  indices_.resize(n);
  normals_.resize(n);
  for (int j = 0; j < res_; ++j)
    for (int i = 0; i < res_; ++i) {
      Vec2 s = slopeScale * source.gradient(Vec2((i + 0.5f) / res_, (j + 0.5f) / res_));
      if (!std::isfinite(s.x) || !std::isfinite(s.y)) s = Vec2(0.0f);
      const Vec3 m = glm::normalize(Vec3(-s.x, -s.y, 1.0f));
      normals_[offset(i, j)] = m;
      indices_[offset(i, j)] = table.invert(m);
    }
}

size_t IndexTexture::offset(int i, int j) const {
  i %= res_, j %= res_;
  if (i < 0) i += res_;
  if (j < 0) j += res_;
  return static_cast<size_t>(j) * res_ + i;
}

Vec2 IndexTexture::index(int i, int j) const { return indices_[offset(i, j)]; }

Vec2 IndexTexture::index(Vec2 p) const {
  const float x = p.x * res_ - 0.5f, y = p.y * res_ - 0.5f;
  if (!std::isfinite(x) || !std::isfinite(y)) return Vec2(0.5f);
  const float fx = std::floor(x), fy = std::floor(y);
  // Wrap the texel index into range first: floats far from 0 would overflow an int.
  const int i = static_cast<int>(std::fmod(fx, static_cast<float>(res_))),
            j = static_cast<int>(std::fmod(fy, static_cast<float>(res_)));
  const float a = x - fx, b = y - fy;
  const Vec2 p0 = index(i, j) + a * (index(i + 1, j) - index(i, j));
  const Vec2 p1 = index(i, j + 1) + a * (index(i + 1, j + 1) - index(i, j + 1));
  return p0 + b * (p1 - p0);
}

Vec3 IndexTexture::normal(const SynthesisSampler& sampler, Vec2 p, float amplitude, float c) const {
  const Vec2 r = index(p);
  if (!(amplitude > 0.0f)) return sampler.table().lookup(r);
  const TurbulenceCdf& G = sampler.cdf();
  const Vec2 t = (G.inverse(r, c) + amplitude * sampler.turbulence().evaluate(p, c)) *
                 (1.0f / std::sqrt(1.0f + amplitude * amplitude));
  return sampler.table().lookup(G.G(t, c));
}

}  // namespace meso
