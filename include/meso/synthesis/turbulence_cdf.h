// Kautz et al. 2001, section 4: G, the numerically computed CDF of the turbulence's own value
// distribution, so that G(turbulence) is uniform on [0, 1] before it indexes L(r1, r2).
#pragma once

#include "meso/core/piecewise_cdf.h"
#include "meso/synthesis/turbulence.h"

#include <array>
#include <cstdint>
#include <vector>

namespace meso {

struct TurbulenceCdfOptions {
  int points = 1 << 18;  // random sample points per tabulated octave count
  int bins = 1024;       // histogram bins over [-maxAbs, maxAbs]
  uint64_t seed = 0x47636466ull;
  float domain = 4096.0f;  // points are uniform in [0, domain)^2 (units of the surface parameter)
};

// G(t; c): the CDF of one turbulence channel's value t over the plane, at octave count c.
// The paper assumes one distribution for all octave counts; the normalized turbulence nearly
// has that (quantiles move by < 0.003 from c = 1 to c = 4, and not at all beyond), and this class
// tabulates what is left:
//  - measured rows at c = kMeasuredCounts, each from `points` random points, both channels and
//    their negatives (gradient noise is symmetric, which halves the error of the odd part); the
//    statistical error of a row's CDF is about 0.5 / sqrt(4 points);
//  - rows every 1/16 octave from c = 1 to 4 made by blending the measured rows' quantile
//    functions (displacement interpolation: right where the spread and the tails move, where
//    blending CDFs would not be), linearly in s(c) = floor(c) + w_floor(c)(c)^2 (the fading
//    octave's share changes the normalized shape at second order in its weight); quantiles are
//    crowded towards 0 and 1 (as L's nodes), each row a piecewise-linear CDF over `bins` bins;
//  - at run time the two fine rows around c blend linearly; c < 1 uses the row c = 1 (the first
//    octave fading in from t = 0 maps to r = 1/2, the median), c > 4 the last row.
// Building costs about points * 1.4 us; G() and inverse() are allocation-free and thread-safe.
class TurbulenceCdf {
 public:
  static constexpr std::array<float, 8> kMeasuredCounts{1.0f, 1.25f, 1.5f, 1.75f,
                                                        2.0f, 2.5f,  3.0f, 4.0f};
  static constexpr int kRowsPerOctave = 16;

  TurbulenceCdf(const Turbulence& turbulence, const TurbulenceCdfOptions& options);
  explicit TurbulenceCdf(const Turbulence& turbulence)
      : TurbulenceCdf(turbulence, TurbulenceCdfOptions{}) {}

  // G(t; c) in [0, 1], nondecreasing in t.
  float G(float t, float c) const;
  Vec2 G(Vec2 t, float c) const { return Vec2(G(t.x, c), G(t.y, c)); }
  // The smallest t with G(t; c) = u (u clamped to [0, 1]).
  float inverse(float u, float c) const;
  Vec2 inverse(Vec2 u, float c) const { return Vec2(inverse(u.x, c), inverse(u.y, c)); }

  float range() const { return range_; }  // G is tabulated over [-range, range]

 private:
  // The fine rows around c, blended (the last two at w = 1 beyond the last row).
  CdfRows blended(float c) const;
  int rowCount_ = 0;
  int bins_;
  float range_;
  std::vector<float> cdf_;  // rows of bins + 1 edges
};

}  // namespace meso
