// Becker & Max 1993, eq. (10) and sections 2.3 and 4.2.
#include "meso/render/transition.h"

#include "meso/core/error.h"
#include "meso/render/shading.h"

#include <algorithm>
#include <cmath>
#include <optional>

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

float levelD(const ReliefLevel& level, const TransitionSettings& settings) {
  return level.source && level.source->texelsPerSide() > 0 ? settings.D * kHeightImageDScale
                                                           : settings.D;
}

namespace {

// The settings with D = levelD: looked up once per level (a virtual call on the height source).
TransitionSettings levelSettings(const ReliefLevel& level, const TransitionSettings& settings) {
  TransitionSettings s = settings;
  s.D = levelD(level, settings);
  return s;
}

}  // namespace

float levelTransition(const ReliefLevel& level, float lengthPerU, float cosThetaV, float distance,
                      float pixelsPerRadian, const TransitionSettings& settings) {
  return transitionParameter(level.wavelength() * lengthPerU,
                             level.longestWavelength() * lengthPerU, pixelsPerRadian, distance,
                             std::abs(cosThetaV), levelSettings(level, settings));
}

LevelTransitions levelTransitions(const MaterialRelief& relief, const SurfacePoint& sp,
                                  const ReliefCoord& coord, const Vec3& eye, float pixelsPerRadian,
                                  const TransitionSettings& settings, DisplacementMode mode,
                                  std::span<const Light> lights, TransitionsFor use,
                                  float smoothLengthPerU) {
  LevelTransitions out;
  const int n =
      static_cast<int>(std::min(relief.levels.size(), static_cast<size_t>(kMaxReliefLevels)));
  out.count = n;
  const Vec3 toEye = eye - sp.P;
  const float distance = glm::length(toEye);
  const Vec3 V = distance > 0.0f && std::isfinite(distance) ? toEye / distance : sp.N;
  const float lengthPerU =
      smoothLengthPerU > 0.0f ? smoothLengthPerU : std::max(glm::length(sp.Pu), glm::length(sp.Pv));
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
    // nu < D; 0 between the level's shortest and longest wavelengths), so the largest T is T at
    // the smallest or the largest |cos|: one evaluation.
    float lo = std::abs(glm::dot(f.N, V)), hi = lo;
    for (size_t k = 0; k < lights.size(); ++k) {
      const float c = std::abs(glm::dot(f.N, k < kept ? L[k] : sampleLight(lights[k], sp.P).L));
      lo = std::min(lo, c);
      hi = std::max(hi, c);
    }
    const TransitionSettings s = levelSettings(level, settings);
    const float shortest = level.wavelength() * lengthPerU;
    const float longest = level.longestWavelength() * lengthPerU;
    const float atLo = transitionParameter(shortest, longest, pixelsPerRadian, distance, lo, s);
    out.T[i] = atLo > 0.0f ? atLo
                           : std::max(atLo, transitionParameter(shortest, longest, pixelsPerRadian,
                                                                distance, hi, s));
    out.weights[i] = transitionWeights(out.T[i], settings);
    out.disp[i] = mode == DisplacementMode::Full ? 1.0f
                  : flat || i < flatUntil        ? 0.0f
                                                 : out.weights[i].disp;
    if (level.partialSum && out.disp[i] < 1.0f)
      flatUntil = std::max(flatUntil, static_cast<int>(level.partialSumEnd));
    if (out.disp[i] > 0.0f) {
      out.raised = i + 1;
      const ReliefLevel& drawn = level.partialSum && out.disp[i] < 1.0f ? *level.partialSum : level;
      if (use == TransitionsFor::Offsets && i + 1 == n) {
        out.H[i] = drawn.height(coord);  // no finer level needs the frame this one raises
      } else {
        out.H[i] = drawn.heightAndDerivatives(coord, out.B[i]);
        out.frames[i + 1] = nextFrame(f, out.disp[i] * out.B[i]);
      }
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

SolidSpace solidSpace(const Material& material, const Mat4& transform, std::string* warning) {
  SolidSpace s;
  if (material.relief.empty() || material.relief.front().source != ReliefSource::Solid) return s;
  s.active = true;
  if (material.relief.front().worldSpace) return s;
  const Mat3 m(transform);
  const float det = glm::determinant(m);
  if (!(std::abs(det) > 0.0f) || !std::isfinite(det)) return s;  // the scene reader refuses these
  s.linear = glm::inverse(m);
  s.offset = -(s.linear * Vec3(transform[3]));
  s.lengthPerUnit = std::cbrt(std::abs(det));
  // Uneven scale: the columns' lengths (the scale along each object axis) differ.
  const float a = glm::length(m[0]), b = glm::length(m[1]), c = glm::length(m[2]);
  const float spread = std::max({a, b, c}) / std::min({a, b, c});
  if (warning && spread > 1.01f)
    *warning = "the object's transform scales unevenly (" + std::to_string(spread) +
               "x between axes): its solid relief is stretched, while its tables are built for "
               "an isotropic relief; use space = \"world\" or an even scale";
  return s;
}

SurfacePoint reliefChart(const SurfacePoint& sp, const SolidSpace& space, ReliefCoord& coord) {
  if (!space.active) {
    coord = ReliefCoord{sp.uv};
    return sp;
  }
  const Vec3 N = sp.N;
  // A tangent's part in the tangent plane, unless it is lost in rounding (a tangent along N).
  const auto tangent = [&](const Vec3& P) {
    const Vec3 t = P - glm::dot(P, N) * N;
    const float length = glm::length(t);
    return length > 1e-3f * glm::length(P) && length > 1e-30f && std::isfinite(length)
               ? std::optional<Vec3>(t)
               : std::nullopt;
  };
  const Vec3 t = tangent(sp.Pu).value_or(
      tangent(sp.Pv).value_or(glm::cross(N, std::abs(N.x) < 0.9f ? Vec3(1, 0, 0) : Vec3(0, 1, 0))));
  const Vec3 e = glm::normalize(t);
  SurfacePoint out = sp;
  out.Pu = space.lengthPerUnit * e;
  out.Pv = space.lengthPerUnit * glm::cross(N, e);
  coord.uv = sp.uv;
  coord.p = space.linear * sp.P + space.offset;
  coord.pu = space.linear * out.Pu;
  coord.pv = space.linear * out.Pv;
  return out;
}

}  // namespace meso
