// The reference of `meso trade`, refined until it converges (see reference_study.h).
#include "meso/trade/reference_study.h"

#include "meso/core/error.h"
#include "meso/render/local_contrast.h"
#include "meso/trade/image_errors.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

namespace meso::trade {
namespace {

// The level's render with the scene's seed (second false) or with the second seed, as the cache
// stores a render: both carry the first render's costs (the second's are not measured).
ReferenceRender toCache(const MeasuredRender& r, bool second) {
  ReferenceRender out;
  out.seconds = r.seconds, out.peakRssMib = r.peakRssMib, out.geometryMib = r.geometryMib;
  out.addedMib = r.addedMib;
  out.micropolygons = r.micropolygons;
  const std::vector<RgbImage>& beauty = second ? r.secondBeauty : r.beauty;
  const std::vector<std::vector<float>>& depth = second ? r.secondDepth : r.depth;
  for (size_t f = 0; f < beauty.size(); ++f) {
    out.width = beauty[f].width, out.height = beauty[f].height;
    const std::vector<float>& rgb = beauty[f].rgb;
    std::vector<float> rgbz(depth[f].size() * 4);
    for (size_t i = 0; i < depth[f].size(); ++i)
      for (int c = 0; c < 4; ++c) rgbz[4 * i + c] = c < 3 ? rgb[3 * i + c] : depth[f][i];
    out.frames.push_back(std::move(rgbz));
  }
  return out;
}

// Beauty and depth of each frame of a cached render.
void splitFrames(const ReferenceRender& r, std::vector<RgbImage>& beauty,
                 std::vector<std::vector<float>>& depth) {
  for (const std::vector<float>& rgbz : r.frames) {
    const size_t n = rgbz.size() / 4;
    RgbImage b{r.width, r.height, std::vector<float>(n * 3)};
    std::vector<float> z(n);
    for (size_t i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c) b.rgb[3 * i + c] = rgbz[4 * i + c];
      z[i] = rgbz[4 * i + 3];
    }
    beauty.push_back(std::move(b));
    depth.push_back(std::move(z));
  }
}

MeasuredRender fromCache(const ReferenceRender& r, const ReferenceRender& second) {
  MeasuredRender out;
  out.seconds = r.seconds, out.peakRssMib = r.peakRssMib, out.geometryMib = r.geometryMib;
  out.addedMib = r.addedMib;
  out.micropolygons = r.micropolygons;
  splitFrames(r, out.beauty, out.depth);
  splitFrames(second, out.secondBeauty, out.secondDepth);
  return out;
}

// The change from `previous` to `level` over the pixels where both hit a surface (the background
// would dilute it), per depth band (quantiles of the level's depth: equal pixel counts, near to
// far) and as an rmse, in percent of the level's mean there, averaged over the frames.
void measureChange(ReferenceLevel& level, const MeasuredRender& previous) {
  const MeasuredRender& now = level.render;
  std::vector<double> bandPct(kDepthBands, 0.0);
  double rmsePct = 0.0;
  for (size_t f = 0; f < now.beauty.size(); ++f) {
    const std::vector<float>& za = now.depth[f];
    const std::vector<float>& zb = previous.depth[f];
    std::vector<size_t> hits;
    for (size_t i = 0; i < za.size(); ++i)
      if (za[i] > 0.0f && zb[i] > 0.0f) hits.push_back(i);
    if (hits.empty()) continue;
    std::sort(hits.begin(), hits.end(), [&](size_t i, size_t j) { return za[i] < za[j]; });
    rmsePct += frameChange(now.beauty[f].rgb, previous.beauty[f].rgb, hits, bandPct);
  }
  const double frames = static_cast<double>(now.beauty.size());
  level.bandChangePct.clear();
  level.meanChangePct = 0.0;
  for (double pct : bandPct) {
    level.bandChangePct.push_back(pct / frames);
    if (std::abs(pct / frames) > std::abs(level.meanChangePct)) level.meanChangePct = pct / frames;
  }
  level.rmseChangePct = rmsePct / frames;
}

// Both renders of a level from the cache (the second under the key of the second seed), or
// nothing: either is missing, bad (a warning) or of other frames.
std::optional<MeasuredRender> cachedLevel(const ReferenceCache& cache, uint64_t key,
                                          uint64_t secondKey, size_t frames) {
  std::string warning;
  std::optional<ReferenceRender> first = cache.load(key, &warning);
  std::optional<ReferenceRender> second;
  if (first) second = cache.load(secondKey, &warning);
  if (!warning.empty()) std::fprintf(stderr, "meso: warning: %s\n", warning.c_str());
  if (!first || !second || first->frames.size() != frames || second->frames.size() != frames ||
      first->width != second->width || first->height != second->height)
    return std::nullopt;
  return fromCache(*first, *second);
}

ReferenceLevel referenceLevel(const Scene& scene, float rate, int spp,
                              const std::vector<CameraSettings>& cams, const ReferenceCache& cache,
                              const MeasureOptions& measure, bool quiet) {
  ReferenceLevel level;
  level.dicingRate = rate, level.spp = spp;
  level.reliefSamples = scene.render.reliefSamples;
  const Configuration c{
      .name = "reference", .kind = Kind::Reference, .D = 0.0f, .spp = spp, .dicingRate = rate};
  const Scene reference = sceneFor(scene, c);
  Scene secondReference = reference;
  secondReference.render.seed = secondSeed(reference.render.seed);
  const uint64_t key = referenceKey(reference, cams, rate, spp);
  const uint64_t secondKey = referenceKey(secondReference, cams, rate, spp);
  if (std::optional<MeasuredRender> cached = cachedLevel(cache, key, secondKey, cams.size())) {
    level.render = std::move(*cached);
    level.fromCache = true;
    if (!quiet)
      std::fprintf(stderr, "meso: trade: reference %g px, %d spp from cache %s\n", rate, spp,
                   cache.fileFor(key).string().c_str());
    return level;
  }
  MeasureOptions noFilms = measure;
  noFilms.keepFilms = false;
  level.render = renderMeasured(scene, c, cams, noFilms);
  try {
    if (level.render.coarsening <= 1.0f) {
      cache.store(key, toCache(level.render, false));
      cache.store(secondKey, toCache(level.render, true));
    }
  } catch (const Error& e) {  // a cache that cannot be written costs time, not the result
    std::fprintf(stderr, "meso: warning: reference not cached: %s\n", e.what());
  }
  return level;
}

// Why the study should stop after level k (not converged), or nothing: refine further.
std::optional<std::string> budgetSpent(const ReferenceLevel& level, int k, float rate,
                                       const ReferenceBudget& b) {
  if (k >= b.maxRefinements)
    return "--reference-max-refinements " + std::to_string(b.maxRefinements) + " reached";
  // Halving the dicing rate gives up to 4x the micropolygons (fewer where texels cap it).
  const double next = 4.0 * static_cast<double>(level.render.micropolygons);
  if (next <= static_cast<double>(b.maxMicropolygons)) return std::nullopt;
  return fmt::format(
      "the next level ({:g} px) would need about {:.3g} micropolygons, over "
      "--reference-max-micropolygons {}",
      rate / 2.0f, next, b.maxMicropolygons);
}

// What remains if the changes keep shrinking as they did over the last two levels (a geometric
// series); negative when there are fewer than three levels or the changes did not shrink.
double remainingEstimatePct(const ReferenceStudy& s) {
  const size_t n = s.levels.size();
  if (n < 3) return -1.0;
  const double last = std::abs(s.levels[n - 1].meanChangePct),
               before = std::abs(s.levels[n - 2].meanChangePct);
  if (!(before > 0.0) || !(last < before)) return -1.0;
  const double q = last / before;
  return last * q / (1.0 - q);
}

// "0.5 px 64 spp -> 0.25 px 128 spp (mean +1.2%, rmse 0.9%) -> ..."
std::string referenceLevels(const ReferenceStudy& s) {
  std::string text;
  for (size_t k = 0; k < s.levels.size(); ++k) {
    const ReferenceLevel& l = s.levels[k];
    if (k == 0)
      text += fmt::format("{:g} px {:g}/wavelength {} spp", l.dicingRate, l.reliefSamples, l.spp);
    else
      text += fmt::format(" -> {:g} px {:g}/wavelength {} spp (worst band {:+.2f}%, rmse {:.2f}%)",
                          l.dicingRate, l.reliefSamples, l.spp, l.meanChangePct, l.rmseChangePct);
  }
  return text;
}

}  // namespace

ReferenceStudy convergeReference(const Scene& base, const ReferenceBudget& budget,
                                 const std::vector<CameraSettings>& cams,
                                 const ReferenceCache& cache, const MeasureOptions& measure,
                                 bool quiet) {
  Scene scene = base;
  scene.render.maxMicropolygons =
      std::max<int64_t>(scene.render.maxMicropolygons, budget.maxMicropolygons);
  ReferenceStudy study;
  study.tolerance = budget.tolerance;
  study.rmseTolerance = budget.rmseTolerance;
  float rate = budget.dicingRate;
  int spp = budget.spp;
  for (int k = 0;; ++k) {
    study.levels.push_back(referenceLevel(scene, rate, spp, cams, cache, measure, quiet));
    ReferenceLevel& level = study.levels.back();
    if (!quiet)
      std::fprintf(stderr,
                   "meso: trade: reference level %d: %g px, %g per wavelength, %d spp, %zu "
                   "micropolygons, %.3g s%s\n",
                   k, rate, scene.render.reliefSamples, spp, level.render.micropolygons,
                   level.render.seconds, level.fromCache ? " (cached)" : "");
    if (level.render.coarsening > 1.0f) {
      study.stop = "the micropolygon cap coarsened level " + std::to_string(k);
      if (study.levels.size() > 1) study.levels.pop_back();  // the finest level diced as asked
      return study;
    }
    if (k > 0) {
      measureChange(level, study.levels[k - 1].render);
      if (std::abs(level.meanChangePct) < budget.tolerance &&
          level.rmseChangePct < budget.rmseTolerance) {
        study.converged = true;
        study.stop = "converged";
        return study;
      }
    }
    if (std::optional<std::string> why = budgetSpent(level, k, rate, budget)) {
      study.stop = *why;
      return study;
    }
    // Each refinement halves the pixel dicing and doubles the micropolygons per relief
    // wavelength (where relief is sub-pixel), up to the relief's texels.
    rate /= 2.0f;
    scene.render.reliefSamples = std::min(16.0f, 2.0f * scene.render.reliefSamples);
    spp = std::min(spp * 2, 65536);
  }
}

std::string referenceVerdict(const ReferenceStudy& s) {
  if (s.converged)
    return fmt::format(
        "reference converged (the mean of every depth band changed by less than {:g}%, the rmse "
        "is below {:g}% of the mean): {}",
        s.tolerance, s.rmseTolerance, referenceLevels(s));
  const ReferenceLevel& last = s.levels.back();
  const double rest = remainingEstimatePct(s);
  const std::string estimate =
      rest >= 0.0 ? fmt::format("; extrapolated, that band is still about {:.2g}% off", rest) : "";
  if (s.levels.size() < 2)
    return fmt::format("reference NOT converged: only one level ({}), {}; its error is unknown",
                       referenceLevels(s), s.stop);
  return fmt::format(
      "reference NOT converged (tolerances: band mean {:g}%, rmse {:g}%): {}; {}; the last "
      "refinement still changed the mean of a depth band by {:+.2f}% and the rmse by {:.2f}% of "
      "the mean{}",
      s.tolerance, s.rmseTolerance, referenceLevels(s), s.stop, last.meanChangePct,
      last.rmseChangePct, estimate);
}

}  // namespace meso::trade
