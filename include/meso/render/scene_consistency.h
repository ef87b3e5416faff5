// Becker & Max 1993, Figure 6 for whole scenes: the mean intensity and the local contrast
// (local_contrast.h) each renderer gives, per object and per band of image rows, against a
// full-displacement reference whose own convergence is measured (the same reference diced twice as
// coarsely).
#pragma once

#include "meso/core/image.h"
#include "meso/core/memory_budget.h"
#include "meso/scene/scene.h"

#include <atomic>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace meso {

struct SceneConsistencyOptions {
  std::vector<Algorithm> algorithms{Algorithm::Bump, Algorithm::Redistribution, Algorithm::Brdf,
                                    Algorithm::Auto};
  int bands = 6;                  // bands of image rows, top to bottom
  float referenceDicing = 0.25f;  // dicing rate of the displacement reference, pixels
  int referenceSpp = 0;           // 0: the scene's spp
  const std::atomic<bool>* cancel = nullptr;
  uint64_t memoryLimitBytes = defaultMemoryLimitBytes();  // PrepareOptions::memoryLimitBytes
  // Called before each render with what it is (e.g. "reference: displacement at 0.25 px").
  std::function<void(const std::string&)> onRender;
};

// One region of the image (an object or a band of rows): its pixel count, mean luminance and local
// contrast per renderer, in the order of SceneConsistencyReport::renderers. A band's contrast
// counts only blocks on one object (an occluding contour is not texture).
struct ConsistencyRegion {
  std::string name;
  int64_t pixels = 0;
  // The largest distance from the eye at which the reference's pixel-centre rays hit it (0: no
  // pixels): the region is diced as asked when this is below referenceAsAskedWithin.
  double farthest = 0.0;
  std::vector<double> mean;
  std::vector<double> contrast;  // C, noise-corrected
  // contrast / the reference's where the reference shows relief (contrastRatio), else NaN.
  std::vector<double> contrastRatio;
};

struct SceneConsistencyReport {
  std::vector<std::string>
      renderers;  // "reference" first, then "coarse reference", then the algorithms
  std::vector<ConsistencyRegion> regions;
  // The worst relative difference of a renderer (not the coarse reference) against the reference
  // over all regions with pixels, and where.
  double worst = 0.0;
  std::string worstRenderer, worstRegion;
  // The largest relative change of the reference when its dicing is halved: how converged it is.
  double referenceChange = 0.0;
  // The micropolygon cap (render.max_micropolygons) coarsened the reference or the coarse
  // reference: then they are not diced as asked, and referenceChange says nothing about regions
  // that reach beyond referenceAsAskedWithin (world units from the eye, the nearer of the two
  // references' AdaptiveTessellationStats::coarsenedBeyond; infinity when not coarsened): the cap
  // coarsens the farthest geometry first, and everything nearer than that is diced as asked.
  bool referenceCoarsened = false;
  double referenceAsAskedWithin = std::numeric_limits<double>::infinity();
  // Detail: the renderers (not the coarse reference) whose contrast ratio leaves 1 -+
  // kContrastTolerance in some region, in the order of renderers; the ratio furthest from 1 of
  // those renderers over all regions (NaN when no region shows relief), and where; the coarse
  // reference's largest |ratio - 1|: how converged the reference's detail is.
  std::vector<std::string> notDetailed;
  double worstContrastRatio = std::numeric_limits<double>::quiet_NaN();
  std::string worstContrastRenderer, worstContrastRegion;
  double referenceContrastChange = 0.0;
  std::vector<std::string> warnings;  // of every render, each once
};

// Renders `scene` (its own camera) with each renderer, each twice with two seeds (the second
// measures sampling noise, local_contrast.h); pixels are grouped by the object the reference's
// pixel-centre ray hits (background pixels belong to no region). Throws Interrupted when cancel is
// set.
SceneConsistencyReport sceneConsistency(const Scene& scene, const SceneConsistencyOptions& options);

// The report as CSV (region, pixels, one column per renderer, then relative differences, then the
// reference's contrast and each other renderer's contrast ratio, empty where the reference shows
// no relief) or as a markdown table ("-" there).
std::string formatSceneConsistency(const SceneConsistencyReport& report, TableFormat format);

}  // namespace meso
