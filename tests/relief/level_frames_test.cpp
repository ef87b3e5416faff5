// Becker & Max 1993, section 2.3: frames of stacked levels.
#include "meso/relief/level_frames.h"
#include "meso/relief/fractal_noise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace meso {
namespace {

using D3 = glm::dvec3;

D3 P(double u, double v) {
  return {1.7 * u + 0.8 * v, 0.5 * v + 0.3 * u * v, 0.5 * u * u - 0.2 * std::cos(3 * v)};
}
double h1(double u, double v) { return std::sin(3 * u + 1) * std::cos(2 * v); }
double h2(double u, double v) { return 0.5 * std::sin(7 * u) * std::sin(5 * v + 0.3); }

constexpr double kStep = 1e-4;
template <typename F>
D3 du(F&& f, double u, double v) {
  return (f(u + kStep, v) - f(u - kStep, v)) / (2 * kStep);
}
template <typename F>
D3 dv(F&& f, double u, double v) {
  return (f(u, v + kStep) - f(u, v - kStep)) / (2 * kStep);
}
template <typename F>
D3 unitNormal(F&& f, double u, double v) {
  return glm::normalize(glm::cross(du(f, u, v), dv(f, u, v)));
}
double dhu(double (*h)(double, double), double u, double v) {
  return (h(u + kStep, v) - h(u - kStep, v)) / (2 * kStep);
}
double dhv(double (*h)(double, double), double u, double v) {
  return (h(u, v + kStep) - h(u, v - kStep)) / (2 * kStep);
}

// Level 2 displaced along the normal of the level-1 displaced surface (the paper's requirement).
double stackedError(double a, double u, double v) {
  const auto P1 = [a](double s, double t) { return P(s, t) + a * h1(s, t) * unitNormal(P, s, t); };
  const auto P2 = [a, &P1](double s, double t) {
    return P1(s, t) + a * h2(s, t) * unitNormal(P1, s, t);
  };
  const D3 exact = unitNormal(P2, u, v);
  const SurfaceFrame limit{Vec3(du(P, u, v)), Vec3(dv(P, u, v)), Vec3(unitNormal(P, u, v))};
  const Vec2 B[2] = {Vec2(a * dhu(h1, u, v), a * dhv(h1, u, v)),
                     Vec2(a * dhu(h2, u, v), a * dhv(h2, u, v))};
  const LevelFrames f = levelFrames(limit, B);
  EXPECT_EQ(f.count, 2);
  return glm::length(D3(f.frames[2].N) - exact);
}

TEST(LevelFrames, StackedLevelsMatchTheDisplacedSurfaceToFirstOrder) {
  for (const auto& [u, v] : {std::pair{0.3, 0.2}, std::pair{-0.6, 0.9}}) {
    double previous = 0.0;
    for (double a : {0.02, 0.01, 0.005}) {
      const double perA = stackedError(a, u, v) / a;
      if (previous > 0.0) {
        EXPECT_GT(perA / previous, 0.35) << a;
        EXPECT_LT(perA / previous, 0.65) << a;
      }
      previous = perA;
    }
  }
}

TEST(LevelFrames, FollowTheUpdateRule) {
  const SurfaceFrame limit{Vec3(2, 0, 0.1f), Vec3(0.5f, 1, 0),
                           glm::normalize(glm::cross(Vec3(2, 0, 0.1f), Vec3(0.5f, 1, 0)))};
  const FractalNoise a(3, 2.0f, 0.5f, 1), b(3, 2.0f, 0.5f, 2);
  const std::vector<HeightLevel> levels = {HeightLevel::make(a, 0.1f, 2.0f),
                                           HeightLevel::make(b, 0.02f, 16.0f)};
  const Vec2 uv(0.37f, 0.61f);
  const LevelFrames f = levelFrames(limit, levels, uv);
  ASSERT_EQ(f.count, 2);
  for (int i = 0; i < 2; ++i) {
    const SurfaceFrame &s = f.frames[i], &t = f.frames[i + 1];
    EXPECT_EQ(f.B[i], levels[i].derivatives(uv));
    EXPECT_LT(glm::length(t.Pu - (s.Pu + f.B[i].x * s.N)), 1e-5f);
    EXPECT_LT(glm::length(t.Pv - (s.Pv + f.B[i].y * s.N)), 1e-5f);
    EXPECT_LT(glm::length(t.N - glm::normalize(glm::cross(t.Pu, t.Pv))), 1e-5f);
  }
  EXPECT_EQ(levelFrames(limit, std::span<const Vec2>()).count, 0);
  EXPECT_THROW(levelFrames(limit, std::vector<Vec2>(kMaxReliefLevels + 1)), std::length_error);
}

TEST(LevelFrames, FiniteAtTheExtremes) {
  const SurfaceFrame flat{Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  const SurfaceFrame degenerate{Vec3(0.0f), Vec3(0, 1, 0), Vec3(0.0f)};
  const std::vector<Vec2> B = {Vec2(1e30f, -1e30f), Vec2(NAN, 1.0f), Vec2(0.0f), Vec2(3e38f, 3e38f),
                               Vec2(0.5f)};
  for (const SurfaceFrame& limit : {flat, degenerate}) {
    const LevelFrames f = levelFrames(limit, B);
    for (int i = 0; i <= f.count; ++i) {
      EXPECT_TRUE(isFinite(f.frames[i].N)) << i;
      EXPECT_TRUE(isFinite(f.frames[i].Pu) && isFinite(f.frames[i].Pv)) << i;
    }
  }
}

}  // namespace
}  // namespace meso
