// A relief of periodic sinusoids for the table tests: integer frequencies, so that it tiles.
#pragma once

#include "meso/appearance/histogram_builder.h"
#include "meso/core/rng.h"

#include <cmath>
#include <cstdint>
#include <vector>

namespace meso {

struct Waves : PeriodicRelief {
  struct Wave {
    float a;
    int fx, fy;
    float phase;
  };
  std::vector<Wave> waves;
  uint64_t seed = 0;  // the fingerprint

  float height(float x, float y) const override {
    float h = 0;
    for (const Wave& w : waves) h += w.a * std::sin(2 * kPi * (w.fx * x + w.fy * y) + w.phase);
    return h;
  }
  Vec2 gradient(float x, float y) const override {
    Vec2 g(0.0f);
    for (const Wave& w : waves) {
      const float c = w.a * 2 * kPi * std::cos(2 * kPi * (w.fx * x + w.fy * y) + w.phase);
      g += Vec2(c * w.fx, c * w.fy);
    }
    return g;
  }
  uint64_t fingerprint() const override { return seed; }
};

// count waves of amplitude 0.5 to 1.5 times `amplitude`, random frequencies fx in [fx0, fx0 + nx)
// and fy in [fy0, fy0 + ny), random phases.
inline Waves randomWaves(uint64_t seed, float amplitude, int count, int fx0, int nx, int fy0,
                         int ny) {
  Waves w;
  w.seed = seed;
  Rng rng(seed);
  for (int i = 0; i < count; ++i)
    w.waves.push_back({amplitude * (0.5f + rng.uniform()),
                       fx0 + static_cast<int>(rng.uniform() * nx),
                       fy0 + static_cast<int>(rng.uniform() * ny), 2 * kPi * rng.uniform()});
  return w;
}

}  // namespace meso
