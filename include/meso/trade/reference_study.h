// The reference of `meso trade`, checked rather than assumed: level k is full displacement at
// dicingRate / 2^k pixels and spp * 2^k samples; refinement stops when, between levels k - 1 and k,
// over the pixels that hit a surface, the mean intensity of each of five depth bands (quantiles,
// near to far) changes by less than `tolerance` and the rmse is below `rmseTolerance`, both in
// percent of the mean (converged; the rmse includes both levels' sampling noise, hence its own
// tolerance), or when the next level would exceed maxRefinements or maxMicropolygons (not
// converged: the verdict gives the last change and an extrapolation of what remains). Each level
// is cached on disk (reference_cache.h), with its second seed's render (the sampling noise of the
// local contrast, render/local_contrast.h) under that seed's key.
#pragma once

#include "meso/scene/scene.h"
#include "meso/trade/measured_render.h"
#include "meso/trade/reference_cache.h"

#include <string>
#include <vector>

namespace meso::trade {

struct ReferenceBudget {
  int spp = 64;
  float dicingRate = 0.5f;                   // pixels
  float tolerance = 0.5f;                    // percent of the mean intensity
  float rmseTolerance = 2.0f;                // percent of the mean intensity
  int maxRefinements = 3;                    // levels after the first
  long long maxMicropolygons = 100'000'000;  // no level is started that would exceed it
};

// One level of the reference's refinement.
struct ReferenceLevel {
  float dicingRate = 0.5f;
  float reliefSamples = 4.0f;  // micropolygon edges per shortest relief wavelength (at least)
  int spp = 64;
  MeasuredRender render;
  bool fromCache = false;
  // Against the previous level, over the pixels where both hit a surface, in percent of this
  // level's mean there (first level: none): the signed change of the mean in each depth band
  // (quantiles of this level's depth), the largest of them in magnitude, and the rmse.
  std::vector<double> bandChangePct;
  double meanChangePct = 0.0, rmseChangePct = 0.0;
};

struct ReferenceStudy {
  std::vector<ReferenceLevel> levels;  // the last one is the reference
  bool converged = false;
  std::string stop;  // why refinement stopped
  float tolerance = 0.5f, rmseTolerance = 2.0f;
  const MeasuredRender& reference() const { return levels.back().render; }
};

// Refines the reference (dicing rate halved, spp doubled) until it converges or the budget ends;
// progress on stderr unless quiet.
ReferenceStudy convergeReference(const Scene& scene, const ReferenceBudget& budget,
                                 const std::vector<CameraSettings>& cameras,
                                 const ReferenceCache& cache, const MeasureOptions& measure,
                                 bool quiet);

// "reference converged (...): 0.5 px 64 spp -> 0.25 px 128 spp (...)" or "reference NOT
// converged ...", with why refinement stopped and an extrapolation of what remains.
std::string referenceVerdict(const ReferenceStudy& study);

}  // namespace meso::trade
