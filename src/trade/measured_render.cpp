// Renders one configuration of `meso trade` and measures it (see measured_render.h).
#include "meso/trade/measured_render.h"

#include "meso/core/timer.h"
#include "meso/render/film_layout.h"
#include "meso/render/integrator.h"
#include "meso/render/local_contrast.h"
#include "meso/render/render_context.h"
#include "meso/trade/peak_rss.h"

#include <algorithm>
#include <cstdio>

namespace meso::trade {
namespace {

std::vector<float> depthOf(const Image& film) {
  std::vector<float> depth(static_cast<size_t>(film.width) * film.height);
  for (int y = 0; y < film.height; ++y)
    for (int x = 0; x < film.width; ++x)
      depth[static_cast<size_t>(y) * film.width + x] = film.at(x, y, FilmLayout::DepthZ);
  return depth;
}

void noteGeometry(MeasuredRender& out, const FrameGeometryStats& geometry) {
  out.micropolygons = std::max(out.micropolygons, geometry.micropolygons);
  out.geometryMib =
      std::max(out.geometryMib, static_cast<double>(geometry.meshBytes + geometry.embreePeakBytes) /
                                    (1024.0 * 1024.0));
  out.coarsening = std::max(out.coarsening, geometry.coarsening);
}

void resetPeakOrWarn(bool* warned) {
  if (resetPeakRss() || (warned && *warned)) return;
  std::fprintf(stderr,
               "meso: warning: cannot reset the peak RSS (/proc/self/clear_refs); peak_rss_mib is "
               "the process-wide peak so far\n");
  if (warned) *warned = true;
}

}  // namespace

RgbImage beautyOf(const Image& film) {
  RgbImage out{film.width, film.height,
               std::vector<float>(static_cast<size_t>(film.width) * film.height * 3)};
  for (int y = 0; y < film.height; ++y)
    for (int x = 0; x < film.width; ++x) {
      float* p = &out.rgb[(static_cast<size_t>(y) * film.width + x) * 3];
      p[0] = film.at(x, y, FilmLayout::R), p[1] = film.at(x, y, FilmLayout::G);
      p[2] = film.at(x, y, FilmLayout::B);
    }
  return out;
}

MeasuredRender renderMeasured(const Scene& base, const Configuration& c,
                              const std::vector<CameraSettings>& cameras,
                              const MeasureOptions& options) {
  const Scene scene = sceneFor(base, c);
  MeasuredRender out;
  resetPeakOrWarn(options.warnedRss);
  const double before = currentRssMib();
  PrepareTimes prep;
  RenderContext ctx = prepareRenderContext(scene, prep,
                                           {.buildFrame = false,
                                            .progress = options.progress,
                                            .memoryLimitBytes = options.memoryLimitBytes});
  RenderCounters counters;
  for (const CameraSettings& cam : cameras) {
    if (options.cancel && options.cancel->load()) throw Interrupted();
    Timer timer;
    const FrameGeometryStats geometry = prepareFrame(ctx, cam, prep);
    const RenderOptions ro{c.spp, scene.render.seed, false, false, options.cancel, true};
    Image film = renderFrame(ctx, ro, counters);
    out.seconds += timer.seconds();
    out.peakRssMib = std::max(out.peakRssMib, peakRssMib());
    noteGeometry(out, geometry);
    out.beauty.push_back(beautyOf(film));
    if (c.kind == Kind::Reference) out.depth.push_back(depthOf(film));
    if (options.keepFilms) out.films.push_back(std::move(film));
    {
      RenderOptions second = ro;
      second.seed = secondSeed(ro.seed);
      const Image secondFilm = renderFrame(ctx, second, counters);
      out.secondBeauty.push_back(beautyOf(secondFilm));
      if (c.kind == Kind::Reference) out.secondDepth.push_back(depthOf(secondFilm));
    }
    resetPeakRss();  // what the second render needed is not the configuration's
  }
  out.addedMib = std::max(0.0, out.peakRssMib - before);
  for (const std::string& w : ctx.warnings.list())
    std::fprintf(stderr, "meso: warning: %s: %s\n", c.name.c_str(), w.c_str());
  return out;
}

}  // namespace meso::trade
