// Becker & Max 1993, Figure 6 for whole scenes (issue: consistency on every real surface).
#include "meso/render/scene_consistency.h"

#include "meso/render/displacement.h"
#include "meso/render/film_layout.h"
#include "meso/render/integrator.h"
#include "meso/render/local_contrast.h"
#include "meso/render/render_context.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace meso {
namespace {

double luminance(const Image& film, int x, int y) {
  return meso::luminance(film.at(x, y, FilmLayout::R), film.at(x, y, FilmLayout::G),
                         film.at(x, y, FilmLayout::B));
}

// The film's luminance, row-major.
std::vector<float> luminanceOf(const Image& film) {
  std::vector<float> y(static_cast<size_t>(film.width) * film.height);
  for (int row = 0; row < film.height; ++row)
    for (int x = 0; x < film.width; ++x)
      y[static_cast<size_t>(row) * film.width + x] = static_cast<float>(luminance(film, x, row));
  return y;
}

struct Rendered {
  Image image;
  LuminanceImage lum;           // of image, and of the same frame rendered with secondSeed
  std::vector<int> object;      // per pixel: the object its centre ray hits, -1 for none
  std::vector<float> distance;  // per pixel: how far from the eye it hits (with `object`)
  float coarsening = 1.0f;      // > 1: the micropolygon cap coarsened dicing
  float coarsenedBeyond = std::numeric_limits<float>::infinity();  // where, FrameGeometryStats
  std::vector<std::string> warnings;
};

// How a reference dices: its dicing rate (pixels), the scene's relief samples times reliefFactor,
// and edges per texel of height images (0: the scene's).
struct ReferenceDicing {
  float rate = 0.0f;
  float reliefFactor = 1.0f;
  float texelSamples = 0.0f;
};

// Edges per texel of the reference and of the coarse reference: a height image's bilinear surface
// keeps curving and casting shadows below its texels, so one edge per texel is far from converged
// (scenes/bricks_plane.toml: one edge per texel is 0.9% darker than eight in the farthest depth
// band; docs/validation.md); 8 and 4 by default, twice the scene's and the scene's if it
// asks for more.
std::pair<float, float> referenceTexelSamples(const Scene& scene) {
  const float sceneEdges =
      ReliefSampling{scene.render.reliefSamples, scene.render.texelSamples}.texelEdges();
  const float fine = std::min(16.0f, std::max(8.0f, 2.0f * sceneEdges));
  return {fine, fine / 2.0f};
}

// algorithm with the dicing of `d` (a rate <= 0 keeps the scene's).
Rendered renderWith(const Scene& base, Algorithm algorithm, const ReferenceDicing& d, int spp,
                    const SceneConsistencyOptions& o, bool objects) {
  Scene scene = base;
  scene.render.algorithm = algorithm;
  if (d.rate > 0.0f) scene.render.dicingRate = d.rate;
  scene.render.reliefSamples = std::min(16.0f, scene.render.reliefSamples * d.reliefFactor);
  if (d.texelSamples > 0.0f) scene.render.texelSamples = d.texelSamples;
  if (spp > 0) scene.camera.spp = spp;
  PrepareTimes times;
  RenderContext ctx = prepareRenderContext(
      scene, times, {.buildFrame = false, .memoryLimitBytes = o.memoryLimitBytes});
  const FrameGeometryStats geometry = prepareFrame(ctx, scene.camera, times);
  RenderOptions options;
  options.spp = scene.camera.spp;
  options.seed = scene.render.seed;
  options.progress = false;
  options.cancel = o.cancel;
  RenderCounters counters;
  Rendered r;
  r.coarsening = geometry.coarsening;
  r.coarsenedBeyond = geometry.coarsenedBeyond;
  r.warnings = ctx.warnings.list();
  r.image = renderFrame(ctx, options, counters);
  RenderOptions second = options;
  second.seed = secondSeed(options.seed);
  r.lum = {r.image.width, r.image.height, luminanceOf(r.image),
           luminanceOf(renderFrame(ctx, second, counters))};
  if (objects) {
    r.object.assign(static_cast<size_t>(r.image.width) * r.image.height, -1);
    r.distance.assign(r.object.size(), 0.0f);
    for (int y = 0; y < r.image.height; ++y)
      for (int x = 0; x < r.image.width; ++x) {
        RayHit hit;
        const Ray ray =
            ctx.camera.generateRay(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
        if (ctx.rays && ctx.rays->intersect(ray, hit)) {
          r.object[static_cast<size_t>(y) * r.image.width + x] = hit.mesh;
          r.distance[static_cast<size_t>(y) * r.image.width + x] = hit.t;  // unit direction
        }
      }
  }
  return r;
}

// The regions (objects, then bands of rows) of the pixels whose centre ray hits an object in the
// reference (images[0]), their mean luminance per image, the reference's change and the worst.
void accumulateRegions(const Scene& scene, const std::vector<Rendered>& images, int bands,
                       SceneConsistencyReport& report) {
  const Image& ref = images[0].image;
  const std::vector<int>& object = images[0].object;
  const size_t numObjects = scene.objects.size();
  report.regions.resize(numObjects + static_cast<size_t>(bands));
  for (size_t k = 0; k < numObjects; ++k)
    report.regions[k].name =
        "object " + std::to_string(k) + " (" + scene.objects[k].mesh.filename().string() + ")";
  for (int b = 0; b < bands; ++b)
    report.regions[numObjects + b].name = "rows " + std::to_string(b * ref.height / bands) + "-" +
                                          std::to_string((b + 1) * ref.height / bands - 1);
  for (ConsistencyRegion& r : report.regions) r.mean.assign(images.size(), 0.0);
  for (int y = 0; y < ref.height; ++y)
    for (int x = 0; x < ref.width; ++x) {
      const int obj = object[static_cast<size_t>(y) * ref.width + x];
      if (obj < 0) continue;
      ConsistencyRegion* regions[2] = {&report.regions[obj],
                                       &report.regions[numObjects + y * bands / ref.height]};
      for (ConsistencyRegion* r : regions) {
        r->pixels += 1;
        r->farthest = std::max(r->farthest,
                               double(images[0].distance[static_cast<size_t>(y) * ref.width + x]));
        for (size_t i = 0; i < images.size(); ++i) r->mean[i] += luminance(images[i].image, x, y);
      }
    }
  for (ConsistencyRegion& r : report.regions) {
    if (r.pixels == 0) continue;
    for (double& m : r.mean) m /= static_cast<double>(r.pixels);
    const double rel = r.mean[0] > 0.0 ? std::abs(r.mean[1] / r.mean[0] - 1.0) : 0.0;
    report.referenceChange = std::max(report.referenceChange, rel);
    for (size_t i = 2; i < images.size(); ++i) {
      const double d = r.mean[0] > 0.0 ? std::abs(r.mean[i] / r.mean[0] - 1.0) : 0.0;
      if (d > report.worst) {
        report.worst = d;
        report.worstRenderer = report.renderers[i];
        report.worstRegion = r.name;
      }
    }
  }
}

// Each region's local contrast per image, its ratio to the reference's, and the verdicts. Objects
// are labelled by the reference's object map; a band's blocks by band and object, so that a block
// across an occluding contour counts for neither.
void measureContrast(const std::vector<Rendered>& images, int bands,
                     SceneConsistencyReport& report) {
  const std::vector<int>& object = images[0].object;
  const int width = images[0].image.width, height = images[0].image.height;
  const size_t numObjects = report.regions.size() - static_cast<size_t>(bands);
  std::vector<int> bandLabel(object.size(), -1);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t i = static_cast<size_t>(y) * width + x;
      if (object[i] >= 0)
        bandLabel[i] = (y * bands / height) * static_cast<int>(numObjects) + object[i];
    }
  std::vector<std::vector<ContrastSums>> sums(images.size());  // per image, per region
  for (size_t i = 0; i < images.size(); ++i) {
    std::vector<ContrastSums> perObject(numObjects), perBand(numObjects * bands);
    addContrastBlocks(images[i].lum, object, perObject);
    addContrastBlocks(images[i].lum, bandLabel, perBand);
    sums[i] = perObject;
    sums[i].resize(report.regions.size());
    for (size_t k = 0; k < perBand.size(); ++k)
      sums[i][numObjects + k / numObjects].merge(perBand[k]);
  }
  std::vector<bool> failed(images.size(), false);
  for (size_t k = 0; k < report.regions.size(); ++k) {
    ConsistencyRegion& r = report.regions[k];
    for (size_t i = 0; i < images.size(); ++i) {
      r.contrast.push_back(sums[i][k].contrast());
      const double ratio = contrastRatio(sums[i][k], sums[0][k]);
      r.contrastRatio.push_back(ratio);
      if (i == 1 && !std::isnan(ratio))
        report.referenceContrastChange =
            std::max(report.referenceContrastChange, std::abs(ratio - 1.0));
      if (i < 2 || std::isnan(ratio)) continue;
      failed[i] = failed[i] || !asDetailed(ratio);
      if (std::isnan(report.worstContrastRatio) ||
          std::abs(ratio - 1.0) > std::abs(report.worstContrastRatio - 1.0)) {
        report.worstContrastRatio = ratio;
        report.worstContrastRenderer = report.renderers[i];
        report.worstContrastRegion = r.name;
      }
    }
  }
  for (size_t i = 2; i < images.size(); ++i)
    if (failed[i]) report.notDetailed.push_back(report.renderers[i]);
}

}  // namespace

SceneConsistencyReport sceneConsistency(const Scene& scene, const SceneConsistencyOptions& o) {
  SceneConsistencyReport report;
  std::vector<Rendered> images;
  const auto announce = [&](const std::string& what) {
    if (o.onRender) o.onRender(what);
  };
  // The reference is refined in every way geometry resolves relief: half the coarse reference's
  // pixel dicing, twice its micropolygons per relief wavelength where relief is sub-pixel, and
  // twice its edges per texel of height images.
  const float samples = scene.render.reliefSamples;
  const auto [fineTexel, coarseTexel] = referenceTexelSamples(scene);
  announce(fmt::format(
      "reference: displacement at {:g} px, {:g} per relief wavelength, {:g} per texel; and {:g} "
      "px, {:g}, {:g}",
      o.referenceDicing, std::min(16.0f, 2.0f * samples), fineTexel, 2.0f * o.referenceDicing,
      samples, coarseTexel));
  images.push_back(renderWith(scene, Algorithm::Displacement, {o.referenceDicing, 2.0f, fineTexel},
                              o.referenceSpp, o, true));
  report.renderers.push_back("reference");
  images.push_back(renderWith(scene, Algorithm::Displacement,
                              {2.0f * o.referenceDicing, 1.0f, coarseTexel}, o.referenceSpp, o,
                              false));
  report.renderers.push_back("coarse reference");
  for (Algorithm a : o.algorithms) {
    announce(choiceName(a));
    images.push_back(renderWith(scene, a, {}, 0, o, false));
    report.renderers.push_back(choiceName(a));
  }
  report.referenceCoarsened = images[0].coarsening > 1.0f || images[1].coarsening > 1.0f;
  report.referenceAsAskedWithin = std::min(images[0].coarsenedBeyond, images[1].coarsenedBeyond);
  for (const Rendered& r : images)
    for (const std::string& w : r.warnings)
      if (std::find(report.warnings.begin(), report.warnings.end(), w) == report.warnings.end())
        report.warnings.push_back(w);
  accumulateRegions(scene, images, std::max(1, o.bands), report);
  measureContrast(images, std::max(1, o.bands), report);
  return report;
}

std::string formatSceneConsistency(const SceneConsistencyReport& report, TableFormat format) {
  const bool markdown = format == TableFormat::Markdown;
  std::string out;
  const std::string sep = markdown ? " | " : ",";
  out += markdown ? "| region | pixels" : "region,pixels";
  for (const std::string& r : report.renderers) out += sep + r;
  for (size_t i = 1; i < report.renderers.size(); ++i)
    out += sep + report.renderers[i] + " vs reference";
  out += sep + "reference contrast";
  for (size_t i = 1; i < report.renderers.size(); ++i)
    out += sep + report.renderers[i] + " contrast ratio";
  out += markdown ? " |\n" : "\n";
  if (markdown) {
    out += "|---|---";
    for (size_t i = 0; i < 3 * report.renderers.size() - 1; ++i) out += "|---";
    out += "|\n";
  }
  for (const ConsistencyRegion& r : report.regions) {
    if (r.pixels == 0) continue;
    out += (markdown ? "| " : "") + (markdown ? r.name : "\"" + r.name + "\"") + sep +
           std::to_string(r.pixels);
    for (double m : r.mean) out += sep + fmt::format("{:.5f}", m);
    for (size_t i = 1; i < r.mean.size(); ++i)
      out += sep +
             fmt::format("{:+.2f}%", r.mean[0] > 0.0 ? 100.0 * (r.mean[i] / r.mean[0] - 1.0) : 0.0);
    out += sep + fmt::format("{:.4f}", r.contrast.empty() ? 0.0 : r.contrast[0]);
    for (size_t i = 1; i < r.contrastRatio.size(); ++i)
      out += sep + (std::isnan(r.contrastRatio[i]) ? (markdown ? "-" : "")
                                                   : fmt::format("{:.3f}", r.contrastRatio[i]));
    out += markdown ? " |\n" : "\n";
  }
  return out;
}

}  // namespace meso
