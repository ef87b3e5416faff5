// Kautz et al. 2001, section 7: "generate an NDF for an existing bump map and then use the NDF for
// shading of the bump map" - an NDF from a relief level's slopes.
#pragma once

#include "meso/relief/height_source.h"
#include "meso/relief/slope_covariance.h"
#include "meso/synthesis/ndf.h"

#include <memory>

namespace meso {

enum class NdfModel {
  Beckmann,   // anisotropic Beckmann from the slope covariance, in its principal frame
  Tabulated,  // a histogram of the normal's (x, y) (TabulatedNdf)
};

struct NdfEstimateOptions {
  NdfModel model = NdfModel::Beckmann;
  int samples = 256;  // gradient samples per axis over the tile [0, 1)^2, at texel centres
  // Slope per unit of gradient: the normal of the relief is normalize(-s grad h, 1). For a level
  // whose tile coordinates are S u with world height amplitude * h, and u in world units, that is
  // amplitude * S (HeightLevel::derivatives); 1 takes the source's own units.
  float slopeScale = 1.0f;
  int tableResolution = 64;  // cells per axis of the tabulated NDF
};

struct NdfEstimate {
  std::unique_ptr<Ndf> ndf;
  // The NDF's x axis is the relief's x axis rotated by this angle (radians, in (-pi/2, pi/2]):
  // the direction of largest slope variance. 0 for tabulated NDFs (already in the relief frame).
  // A renderer passes T' = cos(angle) T + sin(angle) B as the tangent (ndfTangent()).
  float principalAngle = 0.0f;
  // K = mean of (s_x, s_y)^T (s_x, s_y) over the samples (second moments about 0, the Beckmann
  // mean slope), in the relief's frame.
  SlopeCovariance covariance;
};

// Beckmann: eigen-decomposition K = R diag(l1, l2) R^T; the slopes of a Beckmann NDF have variance
// alpha^2 / 2 per principal axis, so alpha_x = sqrt(2 l1), alpha_y = sqrt(2 l2), each at least
// 1e-4 (a flat relief gives the sharpest Beckmann rather than a degenerate one).
// Tabulated: each sample's normal adds one count to its (x, y) cell; D is proportional to the count
// (TabulatedNdf normalizes it). meso::Error for samples < 2 or a non-finite slope scale.
NdfEstimate estimateNdf(const HeightSource& source, const NdfEstimateOptions& options = {});

// The world tangent of an NDF's principal x axis: T rotated by angle about N (T made orthogonal
// to N first).
Vec3 ndfTangent(const Vec3& N, const Vec3& T, float principalAngle);

}  // namespace meso
