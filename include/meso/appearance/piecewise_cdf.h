// Monotone piecewise-linear CDFs over equal bins, and their exact inverses (used by redistribution).
#pragma once

#include <span>
#include <vector>

namespace meso {

// Cumulative masses at the n + 1 bin edges of [lo, lo + n * width], normalized so the last is 1.
// All-zero masses give the uniform CDF (so the maps stay defined for empty distributions).
std::vector<float> cumulativeFromMasses(std::span<const float> masses);

// How mass spreads inside a bin: evenly in x, or evenly in solid angle when x is a polar angle
// (uniform in cos x), which is right near the pole where the density per solid angle is smooth.
enum class BinShape { Uniform, SolidAngle };

// The CDF of a mixture (1 - w) * A + w * B of two cumulative tables (w in [0, 1]), evaluated at x;
// mass is spread evenly inside each bin. Allocation-free.
float cdfForward(std::span<const float> a, std::span<const float> b, float w, float lo, float width,
                 float x, BinShape shape = BinShape::Uniform);

// The inverse of cdfForward: the smallest x with F(x) = p (p clamped to [0, 1]), by binary search
// over the edges and linear interpolation inside the bin. Allocation-free.
float cdfInverse(std::span<const float> a, std::span<const float> b, float w, float lo, float width,
                 float p, BinShape shape = BinShape::Uniform);

}  // namespace meso
