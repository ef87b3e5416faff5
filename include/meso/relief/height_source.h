// Becker & Max 1993, section 2.2: the height tables of relief levels, and the paper's quadratic
// (C1 B-spline derivative) bump derivatives.
#pragma once

#include "meso/core/image.h"
#include "meso/core/math.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

namespace meso {

// A height function over the unit tile, in tile coordinates p = (x, y); periodic with period 1
// unless it says otherwise. Heights are the table's own values (amplitude is applied by the level).
class HeightSource {
 public:
  virtual ~HeightSource() = default;
  virtual float height(Vec2 p) const = 0;
  // (dh/dx, dh/dy) in tile coordinates.
  virtual Vec2 gradient(Vec2 p) const = 0;
  // Highest frequency present, in cycles per tile.
  virtual float highestFrequency() const = 0;
  // Hash of everything that shapes height(): the table cache key.
  virtual uint64_t fingerprint() const = 0;
};

enum class BumpDerivativeMethod {
  Quadratic,          // the paper's C1 weights (derivative of the cubic B-spline), default
  CentralDifference,  // eq. (3) over bilinear lookups, one texel apart
};

// A height image: texel (i, j) is centred at ((i + 0.5) / W, (j + 0.5) / H); bilinear heights.
class HeightTable : public HeightSource {
 public:
  HeightTable(int width, int height, std::vector<float> texels, bool periodic = true,
              BumpDerivativeMethod method = BumpDerivativeMethod::Quadratic);
  // One channel, or the luminance (Rec. 709) of RGB / RGBA. `file` names the source in messages.
  static HeightTable fromImage(const Image& image, const std::filesystem::path& file, bool periodic = true);
  // readImage plus the checks of fromImage. Throws meso::Error("FILE: ...").
  static HeightTable load(const std::filesystem::path& file, bool periodic = true);

  float height(Vec2 p) const override;
  Vec2 gradient(Vec2 p) const override;
  float highestFrequency() const override;  // Nyquist: half the texel count, cycles per tile
  uint64_t fingerprint() const override;

  int width() const { return width_; }
  int heightTexels() const { return height_; }
  float texel(int i, int j) const;  // wrapped or clamped
  void setMethod(BumpDerivativeMethod m) { method_ = m; }

 private:
  float rowLerp(int i, float ty) const;  // column i, linearly interpolated at texel row ty
  float colLerp(int j, float tx) const;
  int width_, height_;
  std::vector<float> texels_;
  bool periodic_;
  BumpDerivativeMethod method_;
};

// Periodic gradient-noise fBm (Perlin-style lattice noise with quintic fade) with analytic
// gradients. Octave o has round(baseFrequency * lacunarity^o) lattice cells per tile, so it tiles.
class FractalNoise : public HeightSource {
 public:
  FractalNoise(int octaves, float lacunarity, float gain, uint64_t seed, int baseFrequency = 4);
  float height(Vec2 p) const override;
  Vec2 gradient(Vec2 p) const override;
  float highestFrequency() const override;
  uint64_t fingerprint() const override;

 private:
  // Value and gradient of one octave with `cells` lattice cells per tile.
  float octave(Vec2 p, int cells, uint64_t salt, Vec2& grad) const;
  std::vector<int> cells_;
  std::vector<float> weights_;
  uint64_t seed_;
};

// The Blinn normal of eq. (4) for a surface with derivatives Pu, Pv and height derivatives Bu, Bv:
// N' = normalize(N + Bu (n x Pv) - Bv (n x Pu)) / ... written so that it is the first-order normal
// of the displaced surface P + h n for any (non-orthogonal, stretched) Pu, Pv; `N` is the unit
// normal the result should face like. Never NaN: a degenerate frame returns N.
Vec3 blinnNormal(const Vec3& Pu, const Vec3& Pv, const Vec3& N, float Bu, float Bv);

}  // namespace meso
