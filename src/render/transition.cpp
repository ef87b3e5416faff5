// Becker & Max 1993, eq. (10) and sections 2.3 and 4.2.
#include "meso/render/transition.h"

#include "meso/core/error.h"
#include "meso/render/shading.h"

#include <algorithm>
#include <cmath>

namespace meso {

void validateTransitionSettings(const TransitionSettings& s, const char* where) {
  const float all[] = {s.D, s.eps, s.e1, s.e2, s.e3, s.e4};
  for (float v : all)
    if (!std::isfinite(v))
      throw Error(std::string(where) + ": transition settings must be finite numbers");
  if (s.D < 0.0f) throw Error(std::string(where) + ": D must be >= 0");
  if (s.eps < 0.0f) throw Error(std::string(where) + ": eps must be >= 0");
  if (!thresholdsOrdered(s.e1, s.e2, s.e3, s.e4))
    throw Error(std::string(where) + ": thresholds must satisfy " + kThresholdOrder + ", got " +
                std::to_string(s.e1) + ", " + std::to_string(s.e2) + ", " + std::to_string(s.e3) +
                ", " + std::to_string(s.e4));
}

static_assert(kMaxMaterialReliefLevels == kMaxReliefLevels,
              "the scene reader's level limit is the frames' capacity");

float levelTransition(const ReliefLevel& level, float lengthPerU, float cosThetaV, float distance,
                      float pixelsPerRadian, const TransitionSettings& settings) {
  return transitionParameter(level.wavelength() * lengthPerU, pixelsPerRadian, distance,
                             std::abs(cosThetaV), settings);
}

LevelTransitions levelTransitions(const MaterialRelief& relief, const SurfacePoint& sp,
                                  const Vec3& eye, float pixelsPerRadian,
                                  const TransitionSettings& settings, DisplacementMode mode,
                                  std::span<const Light> lights, TransitionsFor use) {
  LevelTransitions out;
  const int n =
      static_cast<int>(std::min(relief.levels.size(), static_cast<size_t>(kMaxReliefLevels)));
  out.count = n;
  const Vec3 toEye = eye - sp.P;
  const float distance = glm::length(toEye);
  const Vec3 V = distance > 0.0f && std::isfinite(distance) ? toEye / distance : sp.N;
  const float lengthPerU = std::min(glm::length(sp.Pu), glm::length(sp.Pv));
  out.frames[0] = SurfaceFrame{sp.Pu, sp.Pv, sp.N};
  // The directions to the lights, once for every level (a few; more are sampled per level).
  constexpr size_t kKeptLights = 8;
  std::array<Vec3, kKeptLights> L;
  const size_t kept = std::min(lights.size(), kKeptLights);
  for (size_t k = 0; k < kept; ++k) L[k] = sampleLight(lights[k], sp.P).L;
  bool flat =
      false;  // a level left flat leaves every finer one flat (shorter wavelength, same frame)
  // A band of an image not raised whole draws its image's finer bands as one level with it
  // (ReliefLevel::partialSum): they are not raised either.
  int flatUntil = 0;
  for (int i = 0; i < n; ++i) {
    const ReliefLevel& level = relief.levels[i];
    const SurfaceFrame& f = out.frames[i];
    // T is the largest over the view and the lights (the terminator, like the silhouette, section
    // 4.2). (nu - D) / (|cos| + eps) is monotone in |cos| (falling when nu > D, rising when
    // nu < D), so the largest T is T at the smallest or the largest |cos|: one evaluation.
    float lo = std::abs(glm::dot(f.N, V)), hi = lo;
    for (size_t k = 0; k < lights.size(); ++k) {
      const float c = std::abs(glm::dot(f.N, k < kept ? L[k] : sampleLight(lights[k], sp.P).L));
      lo = std::min(lo, c);
      hi = std::max(hi, c);
    }
    const float atLo = levelTransition(level, lengthPerU, lo, distance, pixelsPerRadian, settings);
    out.T[i] = atLo > 0.0f ? atLo
                           : std::max(atLo, levelTransition(level, lengthPerU, hi, distance,
                                                            pixelsPerRadian, settings));
    out.weights[i] = transitionWeights(out.T[i], settings);
    out.disp[i] = mode == DisplacementMode::Full ? 1.0f
                  : flat || i < flatUntil        ? 0.0f
                                                 : out.weights[i].disp;
    if (level.partialSum && out.disp[i] < 1.0f)
      flatUntil = std::max(flatUntil, static_cast<int>(level.partialSumEnd));
    if (out.disp[i] > 0.0f) {
      out.raised = i + 1;
      out.H[i] = level.heightAndDerivatives(sp.uv, out.B[i]);
      out.frames[i + 1] = nextFrame(f, out.disp[i] * out.B[i]);
    } else {
      flat = true;
      out.frames[i + 1] = f;
    }
    if (use == TransitionsFor::Shading && out.weights[i].brdf >= 1.0f) {
      out.count = i + 1;
      break;
    }
  }
  return out;
}

}  // namespace meso
