// Becker & Max 1993, Figure 6 for whole scenes (issue: consistency on every real surface).
#include "meso/render/scene_consistency.h"

#include "meso/render/film_layout.h"
#include "meso/render/integrator.h"
#include "meso/render/render_context.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace meso {
namespace {

struct Rendered {
  Image image;
  std::vector<int> object;  // per pixel: the object its centre ray hits, -1 for none
  float coarsening = 1.0f;  // > 1: the micropolygon cap coarsened dicing
  std::vector<std::string> warnings;
};

// dicing > 0: that dicing rate, and the scene's relief samples times reliefFactor.
Rendered renderWith(const Scene& base, Algorithm algorithm, float dicing, float reliefFactor,
                    int spp, const std::atomic<bool>* cancel, bool objects) {
  Scene scene = base;
  scene.render.algorithm = algorithm;
  if (dicing > 0.0f) scene.render.dicingRate = dicing;
  scene.render.reliefSamples = std::min(16.0f, scene.render.reliefSamples * reliefFactor);
  if (spp > 0) scene.camera.spp = spp;
  PrepareTimes times;
  RenderContext ctx = prepareRenderContext(scene, times, false);
  const FrameGeometryStats geometry = prepareFrame(ctx, scene.camera, times);
  RenderOptions options;
  options.spp = scene.camera.spp;
  options.seed = scene.render.seed;
  options.progress = false;
  options.cancel = cancel;
  RenderCounters counters;
  Rendered r;
  r.coarsening = geometry.coarsening;
  r.warnings = ctx.warnings;
  r.image = renderFrame(ctx, options, counters);
  if (objects) {
    r.object.assign(static_cast<size_t>(r.image.width) * r.image.height, -1);
    for (int y = 0; y < r.image.height; ++y)
      for (int x = 0; x < r.image.width; ++x) {
        RayHit hit;
        const Ray ray =
            ctx.camera.generateRay(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
        if (ctx.rays && ctx.rays->intersect(ray, hit))
          r.object[static_cast<size_t>(y) * r.image.width + x] = hit.mesh;
      }
  }
  return r;
}

double luminance(const Image& film, int x, int y) {
  return 0.2126 * film.at(x, y, FilmLayout::R) + 0.7152 * film.at(x, y, FilmLayout::G) +
         0.0722 * film.at(x, y, FilmLayout::B);
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

}  // namespace

SceneConsistencyReport sceneConsistency(const Scene& scene, const SceneConsistencyOptions& o) {
  SceneConsistencyReport report;
  std::vector<Rendered> images;
  const auto announce = [&](const std::string& what) {
    if (o.onRender) o.onRender(what);
  };
  // The reference is refined in both ways geometry resolves relief: half the coarse reference's
  // pixel dicing, and twice its micropolygons per relief wavelength where relief is sub-pixel.
  const float samples = scene.render.reliefSamples;
  char dicing[128];
  std::snprintf(dicing, sizeof dicing, "%g px, %g and %g px, %g per relief wavelength",
                o.referenceDicing, std::min(16.0f, 2.0f * samples), 2.0f * o.referenceDicing,
                samples);
  announce(std::string("reference: displacement at ") + dicing);
  images.push_back(renderWith(scene, Algorithm::Displacement, o.referenceDicing, 2.0f,
                              o.referenceSpp, o.cancel, true));
  report.renderers.push_back("reference");
  images.push_back(renderWith(scene, Algorithm::Displacement, 2.0f * o.referenceDicing, 1.0f,
                              o.referenceSpp, o.cancel, false));
  report.renderers.push_back("coarse reference");
  for (Algorithm a : o.algorithms) {
    announce(choiceName(a));
    images.push_back(renderWith(scene, a, 0.0f, 1.0f, 0, o.cancel, false));
    report.renderers.push_back(choiceName(a));
  }
  report.referenceCoarsened = images[0].coarsening > 1.0f || images[1].coarsening > 1.0f;
  for (const Rendered& r : images)
    for (const std::string& w : r.warnings)
      if (std::find(report.warnings.begin(), report.warnings.end(), w) == report.warnings.end())
        report.warnings.push_back(w);
  accumulateRegions(scene, images, std::max(1, o.bands), report);
  return report;
}

std::string formatSceneConsistency(const SceneConsistencyReport& report, TableFormat format) {
  const bool markdown = format == TableFormat::Markdown;
  std::string out;
  char buf[64];
  const auto cell = [&](double v, const char* fmt) {
    std::snprintf(buf, sizeof buf, fmt, v);
    return std::string(buf);
  };
  const std::string sep = markdown ? " | " : ",";
  out += markdown ? "| region | pixels" : "region,pixels";
  for (const std::string& r : report.renderers) out += sep + r;
  for (size_t i = 1; i < report.renderers.size(); ++i)
    out += sep + report.renderers[i] + " vs reference";
  out += markdown ? " |\n" : "\n";
  if (markdown) {
    out += "|---|---";
    for (size_t i = 0; i < 2 * report.renderers.size() - 1; ++i) out += "|---";
    out += "|\n";
  }
  for (const ConsistencyRegion& r : report.regions) {
    if (r.pixels == 0) continue;
    out += (markdown ? "| " : "") + (markdown ? r.name : "\"" + r.name + "\"") + sep +
           std::to_string(r.pixels);
    for (double m : r.mean) out += sep + cell(m, "%.5f");
    for (size_t i = 1; i < r.mean.size(); ++i)
      out += sep + cell(r.mean[0] > 0.0 ? 100.0 * (r.mean[i] / r.mean[0] - 1.0) : 0.0, "%+.2f%%");
    out += markdown ? " |\n" : "\n";
  }
  return out;
}

}  // namespace meso
