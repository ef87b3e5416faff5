// Where the hybrid (auto) puts a relief level it draws flat (DESIGN.md section 5): at the mean
// height of the relief the view's rays first hit, so that silhouettes of sub-pixel relief cover the
// pixels displaced relief covers.
#pragma once

#include "meso/core/math.h"

#include <array>
#include <vector>

namespace meso {

struct ReliefLevel;

// A level that BRDF, redistribution or bump draw is flat: its surface is a plane at some height.
// At a silhouette or a mesh boundary, displaced relief covers the pixels beyond that plane as far
// as its rays' first hits reach: a ray that would pass the boundary at height z (from the mean
// plane) is stopped before it exactly when its first hit on the unbounded relief lies above z
// (rays fall monotonically), so the edge moves out by E[h_hit], the mean height of first hits.
// Smith's uncorrelated model gives the hit heights' distribution P(h_hit <= z) = C(z)^(1 + Lambda)
// (C the heights' distribution, Lambda(a) the Gaussian-slope masking function, a = cot(theta) /
// (sqrt(2) sigma)): E[h_hit] = 0 (the mean plane) seen from above and rises towards the highest
// heights at grazing views. So the flat surface of a level is drawn at E[h_hit], not at 0.
class VisibleHeight {
 public:
  VisibleHeight() = default;
  // From 1024 fixed samples of the level's heights and slopes (world units per unit of u).
  // crests false: no crest table (the plane's value at every curvature).
  explicit VisibleHeight(const ReliefLevel& level, bool crests = true);

  // E[h_hit] in world units where cosTheta is the cosine between the view and the level's frame
  // normal and lengthPerU the world length of one unit of u there. On a crest (convex curvature
  // kappa > 0 along the view, 1 / world units, of the levels raised below) the rays that graze it
  // cross the relief over a path the curvature bounds, so its silhouette moves out less than an
  // unbounded plane's: the smaller of the two (buildCrestTable).
  float at(float cosTheta, float lengthPerU, float curvature = 0.0f) const;
  // Whether E[h_hit] can differ from 0 here: Lambda above 1e-5 (a = cot(theta) / (sqrt(2) sigma)
  // below 3), so that callers skip the rest where the view is steep.
  bool grazing(float cosTheta, float lengthPerU) const;

  // Smith's Lambda for Gaussian slopes: (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi)).
  static float smithLambda(float a);

 private:
  static constexpr int kNodes = 57;  // log2(1 + Lambda) in [0, 14], quarter steps
  std::array<float, kNodes> table_{};
  // The crest's edge over the crest's curvature in wavelengths, lambda / R on a unit-speed
  // surface: log2 in [-10, 2], half steps (R from 1024 wavelengths to a quarter of one).
  static constexpr int kCrestNodes = 25;
  static constexpr float kCrestLog2Min = -10.0f;
  static constexpr int kMaxCrestSteps = 2048;  // march steps each side of a crest's top
  std::array<float, kCrestNodes> crest_{};
  float wavelength_ = 0.0f;  // units of u
  void buildCrestTable(const ReliefLevel& level, double lowest, double highest, double mean);
  float slopeRmsPerU_ = 0.0f;  // rms slope per direction (the larger of u and v), per unit of u
  float slopeA(float cot, float lengthPerU) const;
};

}  // namespace meso
