// Environment lighting (docs/environment.md): a latitude-longitude radiance map, importance-sampled
// by its luminance times sin(theta) as a piecewise-constant 2-D distribution (a marginal over rows
// and a conditional per row, core/piecewise_cdf.h), and turned into render.light_samples
// directional lights per camera sample, which every renderer integrates like any other light.
#pragma once

#include "meso/core/image.h"
#include "meso/core/memory_budget.h"
#include "meso/core/math.h"
#include "meso/scene/scene.h"

#include <cstdint>
#include <span>
#include <vector>

namespace meso {

// The map's coordinates: (u, v) in [0, 1)^2, u = x / width across the image, v = y / height down
// it; theta = pi v from the map's up axis (its top row), phi = 2 pi u - pi about it. In the map's
// own frame (up = +y) the direction is (sin theta sin phi, cos theta, -sin theta cos phi): the
// image's centre column faces -z, its right quarter +x. The map frame is turned about +y by
// `rotation` degrees (counter-clockwise seen from above), then by the shortest rotation taking +y
// to `up`.
class EnvironmentMap {
 public:
  // The map of `decl`: its file read and checked (core/texture_lookup.h's readColourImage: a
  // readable image of non-zero size with finite texels >= 0), or a uniform sky of decl.colour.
  // Throws meso::Error naming the file and the scene line of the light, also for a map larger
  // than memoryLimitBytes allows.
  static EnvironmentMap load(const EnvironmentDecl& decl,
                             uint64_t memoryLimitBytes = defaultMemoryLimitBytes());

  // From linear RGB texels (channels 0, 1, 2; top row first), scaled by decl.colour and
  // decl.intensity and turned by decl.rotation and decl.up; decl.file is not read.
  EnvironmentMap(const Image& rgb, const EnvironmentDecl& decl);

  struct Sample {
    Vec3 w{0.0f, 1.0f, 0.0f};  // unit world direction towards the environment
    Vec3 radiance{0.0f};       // L(w)
    float pdf = 0.0f;          // per unit solid angle
  };
  // The direction of xi in [0, 1)^2 by the inverse CDFs (xi.y picks the row, xi.x the column),
  // with its radiance and its density per solid angle, p(u, v) / (2 pi^2 sin theta).
  Sample sample(Vec2 xi) const;
  // L(w) and the density per solid angle that sample() gives w.
  Vec3 radiance(const Vec3& w) const;
  float pdf(const Vec3& w) const;

  // No texel emits: the environment lights nothing (and is not sampled).
  bool black() const { return black_; }
  int width() const { return width_; }
  int height() const { return height_; }

  // World direction of map coordinates (u, v), and back.
  Vec3 direction(Vec2 uv) const;
  Vec2 mapCoordinates(const Vec3& w) const;

 private:
  size_t texelOf(Vec2 uv) const;

  int width_ = 1, height_ = 1;
  std::vector<Vec3> texels_;     // radiance, top row first
  std::vector<float> density_;   // per texel, p(u, v) over the unit square
  std::vector<float> marginal_;  // height_ + 1 edges over the rows
  std::vector<float> rows_;      // height_ rows of width_ + 1 edges over the columns
  Mat3 toWorld_{1.0f};
  bool black_ = true;
};

// The directional lights that stand for the environment in one camera sample: lights.size()
// directions from env.sample, their xi a (0, 2)-sequence in base 2 (van der Corput and Sobol's
// second dimension, so the points of any power of two fill every elementary interval) XOR-scrambled
// by `key` (every point uniform: the estimate is unbiased for any count), each a directional light
// of irradiance L(w) / (pdf(w) n) at normal incidence, n = lights.size(). Summed over the lights,
// kd (L.N) E estimates kd times the irradiance, kd * integral of L(w) (w.N)+ dw.
void environmentLights(const EnvironmentMap& env, uint64_t key, std::span<Light> lights);

// The scramble key of one camera sample (its film position, whose bits are unique per sample, and
// the seed): the same whatever the thread count.
uint64_t environmentSampleKey(Vec2 film, uint64_t seed);

}  // namespace meso
