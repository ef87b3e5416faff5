// `meso trade`: Becker & Max 1993's promise, measured. The paper's D (our render.transition.D, its
// c) trades accuracy for speed; this command renders a full-displacement reference, refines it
// until it converges, and then every configuration of the hybrid (D x spp, and dicing rate x spp at
// the scene's D) and of displacement alone (dicing rate x spp), and reports seconds, peak memory,
// geometry memory, micropolygons and image error against the reference.
//
// The reference is checked, not assumed: level k is full displacement at referenceDicingRate / 2^k
// pixels and referenceSpp * 2^k samples; refinement stops when, between levels k - 1 and k, over
// the pixels that hit a surface, the mean intensity of each of five depth bands (quantiles, near to
// far) changes by less than --reference-tolerance and the rmse is below --reference-rmse-tolerance,
// both in percent of the mean (converged; the rmse includes both levels' sampling noise, hence its
// own tolerance), or when the next level would exceed --reference-max-refinements or
// --reference-max-micropolygons (not converged: a warning gives the last change and an
// extrapolation of what remains). The levels and their changes are in the CSV (comment lines and
// rows reference_l0..) and in the summary. Each level is cached on disk (reference_cache.h).
//
// What is measured (also in docs of the CSV below):
// - seconds: wall time of prepareFrame (tessellation, Embree build) plus renderFrame, summed over
//   the frames. prepareRenderContext (meshes, limit surfaces, relief tables, which are shared by
//   every configuration and cached on disk) is excluded.
// - peak_rss_mib: VmHWM of the process over the configuration. Before each configuration freed heap
//   is returned to the system (malloc_trim) and VmHWM is reset by writing "5" to
//   /proc/self/clear_refs (Linux >= 4.0), so the figure is the peak while that configuration ran,
//   including the baseline the command itself holds (the loaded scene and the kept reference
//   frames). Where the reset is not allowed the column is the process-wide peak so far (monotone),
//   and a warning says so.
// - micropolygons: the most displaced micropolygons of any frame; geometry_mib: the most memory of
//   any frame's displaced meshes and their Embree scene (FrameGeometryStats).
// - errors: of the beauty R, G, B against the reference with OpenImageIO's ImageBufAlgo::compare
//   (mean absolute and RMS difference over pixels and channels) and computePixelStats
//   (mean_intensity_error_pct = 100 |mean(img) - mean(ref)| / mean(ref), means over R, G, B),
//   averaged over the frames.
// Temporal stability (--temporal): for consecutive frames f, f+1 of the default hybrid and of the
// reference, the mean over R, G, B of |beauty(f+1) - beauty(f)| over the pixels whose T.Y in the
// hybrid's frame f lies within --band of e1, e2, e3 or e4 (pixels where no surface was hit are left
// out), pooled over the frame pairs.
#include "trade_command.h"

#include "cli_values.h"
#include "reference_cache.h"
#include "render_command.h"

#include "meso/core/atomic_file.h"
#include "meso/core/error.h"
#include "meso/core/timer.h"
#include "meso/render/integrator.h"
#include "meso/render/render_context.h"
#include "meso/render/transition.h"
#include "meso/scene/camera_path.h"
#include "meso/scene/scene_parser.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <malloc.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

namespace meso::app {
namespace {

namespace fs = std::filesystem;
using OIIO::ImageBuf;

std::atomic<bool> gTradeInterrupted{false};
extern "C" void onTradeInterrupt(int) { gTradeInterrupted.store(true); }

enum class Kind { Reference, Hybrid, Displacement };

struct Configuration {
  std::string name;
  Kind kind = Kind::Hybrid;
  float D = 2.0f;  // hybrid only
  int spp = 4;
  float dicingRate = 1.0f;
  bool defaultHybrid = false;  // D and spp of the scene
};

struct Result {
  Configuration config;
  double seconds = 0.0;
  double peakRssMib = 0.0;
  size_t micropolygons = 0;
  double geometryMib = 0.0;
  double meanAbsError = 0.0, rmse = 0.0, intensityErrorPct = 0.0;
};

// One configuration's frames: beauty as OpenImageIO buffers; whole films only when kept.
struct Rendered {
  double seconds = 0.0;
  double peakRssMib = 0.0;
  size_t micropolygons = 0;
  double geometryMib = 0.0;
  float coarsening = 1.0f;  // > 1: the micropolygon cap coarsened some frame's dicing
  std::vector<ImageBuf> beauty;
  std::vector<std::vector<float>> depth;  // reference levels only: depth.Z per frame (0: no hit)
  std::vector<Image> films;
};

// One level of the reference's refinement.
struct ReferenceLevel {
  float dicingRate = 0.5f;
  int spp = 64;
  Rendered render;
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
  const Rendered& reference() const { return levels.back().render; }
};

const char* algorithmName(Kind k) { return k == Kind::Hybrid ? "auto" : "displacement"; }

std::string formatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// --- options ---

template <class T>
void checkValues(const std::vector<T>& values, const char* option, double lo, double hi) {
  if (values.empty()) throw Error(std::string(option) + ": needs at least one value");
  for (T v : values)
    if (!std::isfinite(static_cast<double>(v)) || v < lo || v > hi)
      throw Error(std::string(option) + ": " + formatNumber(static_cast<double>(v)) +
                  " is outside [" + formatNumber(lo) + ", " + formatNumber(hi) + "]");
}

void validate(const TradeCommandOptions& o) {
  checkValues(std::vector<int>{o.referenceSpp}, "--reference-spp", 1, 65536);
  checkValues(std::vector<float>{o.referenceDicingRate}, "--reference-dicing-rate", 0.01, 1000);
  checkValues(std::vector<float>{o.referenceTolerance}, "--reference-tolerance", 1e-6, 100);
  checkValues(std::vector<float>{o.referenceRmseTolerance}, "--reference-rmse-tolerance", 1e-6,
              1000);
  checkValues(std::vector<int>{o.referenceMaxRefinements}, "--reference-max-refinements", 0, 12);
  checkValues(std::vector<double>{static_cast<double>(o.referenceMaxMicropolygons)},
              "--reference-max-micropolygons", 1000, 1e12);
  checkValues(o.hybridDicingRates, "--hybrid-dicing-rates", 0.01, 1000);
  checkValues(o.dValues, "--d-values", 0, 1e6);
  checkValues(o.sppValues, "--spp-values", 1, 65536);
  checkValues(o.dicingRates, "--dicing-rates", 0.01, 1000);
  if (o.width) checkValues(std::vector<int>{*o.width}, "--width", 1, 16384);
  if (o.height) checkValues(std::vector<int>{*o.height}, "--height", 1, 16384);
  if (o.threads) checkValues(std::vector<int>{*o.threads}, "--threads", 0, 1024);
  checkValues(std::vector<float>{o.band}, "--band", 0, 1e6);
}

std::vector<CameraSettings> cameras(const TradeCommandOptions& o, const Scene& scene) {
  if (scene.path.keys.empty()) {
    if (!o.frames.empty())
      throw Error(scene.file.string() +
                  ": path: --frames needs a [path] with keyframes in the scene");
    return {scene.camera};
  }
  const CameraPath path(scene.path.keys);
  const auto [first, last] = parseFrameRange(o.frames, scene.path.frames);
  std::vector<CameraSettings> result;
  for (int f = first; f <= last; ++f)
    result.push_back(path.frame(f, scene.path.frames, scene.camera));
  return result;
}

// The swept configurations (the reference levels are not among them): the hybrid over D x spp at
// the scene's dicing rate and over dicing rate x spp at the scene's D, displacement alone over
// dicing rate x spp.
std::vector<Configuration> configurations(const TradeCommandOptions& o, const Scene& scene) {
  std::vector<Configuration> list;
  const float sceneD = scene.render.transition.D, sceneRate = scene.render.dicingRate;
  const int sceneSpp = scene.camera.spp;
  const auto hybrid = [&](float D, float rate, int spp) {
    return Configuration{
        "hybrid_D" + formatNumber(D) + "_r" + formatNumber(rate) + "_spp" + std::to_string(spp),
        Kind::Hybrid,
        D,
        spp,
        rate,
        D == sceneD && spp == sceneSpp && rate == sceneRate};
  };
  const auto add = [&](const Configuration& c) {
    for (const Configuration& other : list)
      if (other.name == c.name) return;
    list.push_back(c);
  };
  if (!o.temporalOnly) {
    for (float D : o.dValues)
      for (int spp : o.sppValues) add(hybrid(D, sceneRate, spp));
    for (float rate : o.hybridDicingRates)
      for (int spp : o.sppValues) add(hybrid(sceneD, rate, spp));
  }
  add(hybrid(sceneD, sceneRate, sceneSpp));  // the summary's configuration
  if (!o.temporalOnly)
    for (float rate : o.dicingRates)
      for (int spp : o.sppValues)
        list.push_back({"displacement_r" + formatNumber(rate) + "_spp" + std::to_string(spp),
                        Kind::Displacement, 0.0f, spp, rate, false});
  return list;
}

// --- rendering ---

// Returns freed heap to the system and resets VmHWM; false where /proc/self/clear_refs is not
// writable.
bool resetPeakRss() {
  malloc_trim(0);
  std::ofstream clear("/proc/self/clear_refs");
  if (!clear) return false;
  clear << "5";
  clear.flush();
  return static_cast<bool>(clear);
}

ImageBuf beautyBuffer(const Image& film) {
  const int r = film.channelIndex("R"), g = film.channelIndex("G"), b = film.channelIndex("B");
  if (r < 0 || g < 0 || b < 0) throw Error("trade: the film has no R, G, B channels");
  std::vector<float> rgb(static_cast<size_t>(film.width) * film.height * 3);
  for (int y = 0; y < film.height; ++y)
    for (int x = 0; x < film.width; ++x) {
      float* p = &rgb[(static_cast<size_t>(y) * film.width + x) * 3];
      p[0] = film.at(x, y, r), p[1] = film.at(x, y, g), p[2] = film.at(x, y, b);
    }
  ImageBuf buf(OIIO::ImageSpec(film.width, film.height, 3, OIIO::TypeDesc::FLOAT));
  buf.set_pixels(buf.roi(), OIIO::TypeDesc::FLOAT, rgb.data());
  return buf;
}

Scene sceneFor(const Scene& base, const Configuration& c) {
  Scene scene = base;
  scene.render.algorithm = c.kind == Kind::Hybrid ? "auto" : "displacement";
  if (c.kind == Kind::Hybrid) scene.render.transition.D = c.D;
  scene.render.dicingRate = c.dicingRate;
  scene.camera.spp = c.spp;
  validateTransitionSettings(scene.render.transition, "--d-values");
  return scene;
}

Rendered renderConfiguration(const Scene& base, const Configuration& c,
                             const std::vector<CameraSettings>& cams, bool keepFilms,
                             bool& warnedRss) {
  const Scene scene = sceneFor(base, c);
  Rendered out;
  if (!resetPeakRss() && !warnedRss) {
    std::fprintf(
        stderr,
        "meso: warning: cannot reset the peak RSS (/proc/self/clear_refs); peak_rss_mib is the "
        "process-wide peak so far\n");
    warnedRss = true;
  }
  PrepareTimes prep;
  RenderContext ctx = prepareRenderContext(scene, prep, false);
  RenderCounters counters;
  for (const CameraSettings& cam : cams) {
    if (gTradeInterrupted.load()) throw RenderInterrupted();
    Timer timer;
    const FrameGeometryStats geometry = prepareFrame(ctx, cam, prep);
    const RenderOptions ro{c.spp, scene.render.seed, false, false, &gTradeInterrupted, true};
    Image film;
    try {
      film = renderFrame(ctx, ro, counters);
    } catch (const Interrupted&) {
      throw RenderInterrupted();
    }
    out.seconds += timer.seconds();
    out.micropolygons = std::max(out.micropolygons, geometry.micropolygons);
    out.geometryMib = std::max(
        out.geometryMib,
        static_cast<double>(geometry.meshBytes + geometry.embreePeakBytes) / (1024.0 * 1024.0));
    out.coarsening = std::max(out.coarsening, geometry.coarsening);
    out.beauty.push_back(beautyBuffer(film));
    if (c.kind == Kind::Reference) {
      const int z = film.channelIndex("depth.Z");
      if (z < 0) throw Error("trade: the film has no depth.Z channel");
      std::vector<float> depth(static_cast<size_t>(film.width) * film.height);
      for (int y = 0; y < film.height; ++y)
        for (int x = 0; x < film.width; ++x)
          depth[static_cast<size_t>(y) * film.width + x] = film.at(x, y, z);
      out.depth.push_back(std::move(depth));
    }
    if (keepFilms) out.films.push_back(std::move(film));
  }
  out.peakRssMib = peakRssMib();
  for (const std::string& w : ctx.warnings)
    std::fprintf(stderr, "meso: warning: %s: %s\n", c.name.c_str(), w.c_str());
  return out;
}

// --- errors ---

double meanOverChannels(const ImageBuf& img) {
  const OIIO::ImageBufAlgo::PixelStats s = OIIO::ImageBufAlgo::computePixelStats(img);
  if (s.avg.empty()) throw Error("trade: computePixelStats failed: " + img.geterror());
  double sum = 0.0;
  for (float v : s.avg) sum += v;
  return sum / static_cast<double>(s.avg.size());
}

void addErrors(Result& r, const std::vector<ImageBuf>& images,
               const std::vector<ImageBuf>& reference) {
  double mae = 0.0, rmse = 0.0, pct = 0.0;
  for (size_t f = 0; f < images.size(); ++f) {
    const OIIO::ImageBufAlgo::CompareResults cr =
        OIIO::ImageBufAlgo::compare(images[f], reference[f], 1e30f, 1e30f);
    if (cr.error) throw Error("trade: ImageBufAlgo::compare failed: " + images[f].geterror());
    mae += cr.meanerror;
    rmse += cr.rms_error;
    const double mi = meanOverChannels(images[f]), mr = meanOverChannels(reference[f]);
    pct += mr > 0.0 ? 100.0 * std::abs(mi - mr) / mr : (mi == mr ? 0.0 : 100.0);
  }
  const double n = static_cast<double>(images.size());
  r.meanAbsError = mae / n, r.rmse = rmse / n, r.intensityErrorPct = pct / n;
}

// --- the reference: refined until it converges, cached on disk ---

std::vector<float> rgbOf(const ImageBuf& b) {
  std::vector<float> rgb(static_cast<size_t>(b.spec().width) * b.spec().height * 3);
  b.get_pixels(b.roi(), OIIO::TypeDesc::FLOAT, rgb.data());
  return rgb;
}

ReferenceRender toCache(const Rendered& r) {
  ReferenceRender out;
  out.seconds = r.seconds, out.peakRssMib = r.peakRssMib, out.geometryMib = r.geometryMib;
  out.micropolygons = r.micropolygons;
  for (size_t f = 0; f < r.beauty.size(); ++f) {
    out.width = r.beauty[f].spec().width, out.height = r.beauty[f].spec().height;
    const std::vector<float> rgb = rgbOf(r.beauty[f]);
    std::vector<float> rgbz(r.depth[f].size() * 4);
    for (size_t i = 0; i < r.depth[f].size(); ++i)
      for (int c = 0; c < 4; ++c) rgbz[4 * i + c] = c < 3 ? rgb[3 * i + c] : r.depth[f][i];
    out.frames.push_back(std::move(rgbz));
  }
  return out;
}

Rendered fromCache(const ReferenceRender& r) {
  Rendered out;
  out.seconds = r.seconds, out.peakRssMib = r.peakRssMib, out.geometryMib = r.geometryMib;
  out.micropolygons = r.micropolygons;
  for (const std::vector<float>& rgbz : r.frames) {
    const size_t n = rgbz.size() / 4;
    std::vector<float> rgb(n * 3), depth(n);
    for (size_t i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c) rgb[3 * i + c] = rgbz[4 * i + c];
      depth[i] = rgbz[4 * i + 3];
    }
    ImageBuf buf(OIIO::ImageSpec(r.width, r.height, 3, OIIO::TypeDesc::FLOAT));
    buf.set_pixels(buf.roi(), OIIO::TypeDesc::FLOAT, rgb.data());
    out.beauty.push_back(std::move(buf));
    out.depth.push_back(std::move(depth));
  }
  return out;
}

constexpr int kDepthBands = 5;

// The change from `previous` to `level` over the pixels where both hit a surface (the background
// would dilute it), per depth band (quantiles of the level's depth: equal pixel counts, near to
// far) and as an rmse, in percent of the level's mean there, averaged over the frames.
void measureChange(ReferenceLevel& level, const Rendered& previous) {
  const Rendered& now = level.render;
  std::vector<double> bandPct(kDepthBands, 0.0);
  double rmsePct = 0.0;
  for (size_t f = 0; f < now.beauty.size(); ++f) {
    const std::vector<float> a = rgbOf(now.beauty[f]), b = rgbOf(previous.beauty[f]);
    const std::vector<float>& za = now.depth[f];
    const std::vector<float>& zb = previous.depth[f];
    std::vector<size_t> hits;
    for (size_t i = 0; i < za.size(); ++i)
      if (za[i] > 0.0f && zb[i] > 0.0f) hits.push_back(i);
    if (hits.empty()) continue;
    std::sort(hits.begin(), hits.end(), [&](size_t i, size_t j) { return za[i] < za[j]; });
    double sumA = 0.0, squares = 0.0;
    for (int band = 0; band < kDepthBands; ++band) {
      double bandA = 0.0, bandB = 0.0;
      for (size_t k = hits.size() * band / kDepthBands; k < hits.size() * (band + 1) / kDepthBands;
           ++k)
        for (int c = 0; c < 3; ++c) {
          const double va = a[3 * hits[k] + c], vb = b[3 * hits[k] + c];
          bandA += va, bandB += vb, squares += (va - vb) * (va - vb);
        }
      sumA += bandA;
      bandPct[band] += bandA > 0.0 ? 100.0 * (bandA - bandB) / bandA : 0.0;
    }
    const double n = 3.0 * static_cast<double>(hits.size());
    rmsePct += sumA > 0.0 ? 100.0 * std::sqrt(squares / n) / (sumA / n) : 0.0;
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

ReferenceLevel referenceLevel(const Scene& scene, float rate, int spp,
                              const std::vector<CameraSettings>& cams, const ReferenceCache& cache,
                              bool& warnedRss, bool quiet) {
  ReferenceLevel level;
  level.dicingRate = rate, level.spp = spp;
  const Configuration c{"reference", Kind::Reference, 0.0f, spp, rate, false};
  const uint64_t key = referenceKey(sceneFor(scene, c), cams, rate, spp);
  std::string warning;
  if (std::optional<ReferenceRender> cached = cache.load(key, &warning)) {
    if (cached->frames.size() == cams.size()) {
      level.render = fromCache(*cached);
      level.fromCache = true;
      if (!quiet)
        std::fprintf(stderr, "meso: trade: reference %g px, %d spp from cache %s\n", rate, spp,
                     cache.fileFor(key).string().c_str());
      return level;
    }
  }
  if (!warning.empty()) std::fprintf(stderr, "meso: warning: %s\n", warning.c_str());
  level.render = renderConfiguration(scene, c, cams, false, warnedRss);
  try {
    if (level.render.coarsening <= 1.0f) cache.store(key, toCache(level.render));
  } catch (const Error& e) {  // a cache that cannot be written costs time, not the result
    std::fprintf(stderr, "meso: warning: reference not cached: %s\n", e.what());
  }
  return level;
}

// Refines the reference (dicing rate halved, spp doubled) until it converges or the budget ends.
ReferenceStudy convergeReference(const Scene& base, const TradeCommandOptions& o,
                                 const std::vector<CameraSettings>& cams,
                                 const ReferenceCache& cache, bool& warnedRss) {
  Scene scene = base;
  scene.render.maxMicropolygons =
      std::max<int64_t>(scene.render.maxMicropolygons, o.referenceMaxMicropolygons);
  ReferenceStudy study;
  study.tolerance = o.referenceTolerance;
  study.rmseTolerance = o.referenceRmseTolerance;
  float rate = o.referenceDicingRate;
  int spp = o.referenceSpp;
  for (int k = 0;; ++k) {
    study.levels.push_back(referenceLevel(scene, rate, spp, cams, cache, warnedRss, o.quiet));
    ReferenceLevel& level = study.levels.back();
    if (!o.quiet)
      std::fprintf(stderr,
                   "meso: trade: reference level %d: %g px, %d spp, %zu micropolygons, %.3g s%s\n",
                   k, rate, spp, level.render.micropolygons, level.render.seconds,
                   level.fromCache ? " (cached)" : "");
    if (level.render.coarsening > 1.0f) {
      study.stop = "the micropolygon cap coarsened level " + std::to_string(k);
      if (study.levels.size() > 1)
        study.levels.pop_back();  // the finest level that was diced as asked
      return study;
    }
    if (k > 0) {
      measureChange(level, study.levels[k - 1].render);
      if (std::abs(level.meanChangePct) < o.referenceTolerance &&
          level.rmseChangePct < o.referenceRmseTolerance) {
        study.converged = true;
        study.stop = "converged";
        return study;
      }
    }
    if (k >= o.referenceMaxRefinements) {
      study.stop =
          "--reference-max-refinements " + std::to_string(o.referenceMaxRefinements) + " reached";
      return study;
    }
    // Halving the dicing rate gives up to 4x the micropolygons (fewer where texels cap it).
    const double next = 4.0 * static_cast<double>(level.render.micropolygons);
    if (next > static_cast<double>(o.referenceMaxMicropolygons)) {
      char why[160];
      std::snprintf(why, sizeof why,
                    "the next level (%g px) would need about %.3g micropolygons, over "
                    "--reference-max-micropolygons %lld",
                    rate / 2.0f, next, o.referenceMaxMicropolygons);
      study.stop = why;
      return study;
    }
    rate /= 2.0f;
    spp = std::min(spp * 2, 65536);
  }
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
  char buf[160];
  for (size_t k = 0; k < s.levels.size(); ++k) {
    const ReferenceLevel& l = s.levels[k];
    if (k == 0)
      std::snprintf(buf, sizeof buf, "%g px %d spp", l.dicingRate, l.spp);
    else
      std::snprintf(buf, sizeof buf, " -> %g px %d spp (worst band %+.2f%%, rmse %.2f%%)",
                    l.dicingRate, l.spp, l.meanChangePct, l.rmseChangePct);
    text += buf;
  }
  return text;
}

std::string referenceVerdict(const ReferenceStudy& s) {
  char buf[512];
  if (s.converged) {
    std::snprintf(buf, sizeof buf,
                  "reference converged (the mean of every depth band changed by less than %g%%, "
                  "the rmse is below "
                  "%g%% of the mean): %s",
                  s.tolerance, s.rmseTolerance, referenceLevels(s).c_str());
    return buf;
  }
  const ReferenceLevel& last = s.levels.back();
  const double rest = remainingEstimatePct(s);
  char estimate[160] = "";
  if (rest >= 0.0)
    std::snprintf(estimate, sizeof estimate, "; extrapolated, that band is still about %.2g%% off",
                  rest);
  if (s.levels.size() < 2)
    std::snprintf(buf, sizeof buf,
                  "reference NOT converged: only one level (%s), %s; its error is unknown",
                  referenceLevels(s).c_str(), s.stop.c_str());
  else
    std::snprintf(
        buf, sizeof buf,
        "reference NOT converged (tolerances: band mean %g%%, rmse %g%%): %s; %s; the last "
        "refinement "
        "still changed the mean of a depth band by %+.2f%% and the rmse by %.2f%% of the mean%s",
        s.tolerance, s.rmseTolerance, referenceLevels(s).c_str(), s.stop.c_str(),
        last.meanChangePct, last.rmseChangePct, estimate);
  return buf;
}

// --- outputs ---

void writeText(const fs::path& file, const std::string& text) { writeFileAtomically(file, text); }

// "a;b;c" (near to far).
std::string bandList(const std::vector<double>& bands) {
  std::string text;
  for (size_t b = 0; b < bands.size(); ++b) {
    if (b > 0) text += ';';
    text += formatNumber(bands[b]);
  }
  return text;
}

// Comment lines first: the reference's convergence, one line per level.
std::string csv(const std::vector<Result>& results, const ReferenceStudy& study) {
  std::ostringstream s;
  char line[640];
  s << "# " << referenceVerdict(study) << "\n";
  for (size_t k = 0; k < study.levels.size(); ++k) {
    const ReferenceLevel& l = study.levels[k];
    std::snprintf(
        line, sizeof line,
        "# reference level %zu: dicing_rate %g, spp %d, micropolygons %zu, seconds %.6g%s, "
        "mean_change_pct %s, rmse_change_pct %s, band_change_pct %s\n",
        k, l.dicingRate, l.spp, l.render.micropolygons, l.render.seconds,
        l.fromCache ? " (cached)" : "", k ? formatNumber(l.meanChangePct).c_str() : "",
        k ? formatNumber(l.rmseChangePct).c_str() : "", bandList(l.bandChangePct).c_str());
    s << line;
  }
  s << "name,algorithm,D,spp,dicing_rate,seconds,peak_rss_mib,micropolygons,mean_abs_error,rmse,"
       "mean_intensity_error_pct,geometry_mib\n";
  for (const Result& r : results) {
    const Configuration& c = r.config;
    // D is left empty where the algorithm does not use it (displacement alone).
    const std::string D = c.kind == Kind::Hybrid ? formatNumber(c.D) : "";
    std::snprintf(line, sizeof line, "%s,%s,%s,%d,%g,%.6g,%.1f,%zu,%.6g,%.6g,%.6g,%.1f\n",
                  c.name.c_str(), algorithmName(c.kind), D.c_str(), c.spp, c.dicingRate, r.seconds,
                  r.peakRssMib, r.micropolygons, r.meanAbsError, r.rmse, r.intensityErrorPct,
                  r.geometryMib);
    s << line;
  }
  return s.str();
}

// Indices of the configurations (reference excluded) that no other is both faster and more accurate
// than, sorted by time.
std::vector<size_t> paretoFront(const std::vector<Result>& results) {
  std::vector<size_t> order;
  for (size_t i = 0; i < results.size(); ++i)
    if (results[i].config.kind != Kind::Reference) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return results[a].seconds != results[b].seconds ? results[a].seconds < results[b].seconds
                                                    : results[a].rmse < results[b].rmse;
  });
  std::vector<size_t> front;
  double best = std::numeric_limits<double>::infinity();
  for (size_t i : order)
    if (results[i].rmse < best) front.push_back(i), best = results[i].rmse;
  return front;
}

// --- plot: rmse against seconds (log axis), drawn point by point into an ImageBuf ---

struct Rgb {
  float c[3];
};
constexpr Rgb kBlack{{0.0f, 0.0f, 0.0f}}, kGrey{{0.85f, 0.85f, 0.85f}}, kBlue{{0.1f, 0.35f, 0.85f}},
    kRed{{0.85f, 0.15f, 0.1f}};

class Canvas {
 public:
  Canvas(int w, int h) : buf_(OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::FLOAT)) {
    const float white[3] = {1.0f, 1.0f, 1.0f};
    OIIO::ImageBufAlgo::fill(buf_, white);
    const char* dejavu = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
    if (fs::exists(dejavu)) font_ = dejavu;
  }
  void dot(int x, int y, const Rgb& c) {
    if (x >= 0 && y >= 0 && x < buf_.spec().width && y < buf_.spec().height)
      buf_.setpixel(x, y, c.c, 3);
  }
  void line(double x0, double y0, double x1, double y1, const Rgb& c, int thickness = 1) {
    const int steps = static_cast<int>(std::max(std::abs(x1 - x0), std::abs(y1 - y0))) + 1;
    for (int i = 0; i <= steps; ++i) {
      const double t = static_cast<double>(i) / steps;
      const int x = static_cast<int>(std::lround(x0 + t * (x1 - x0))),
                y = static_cast<int>(std::lround(y0 + t * (y1 - y0)));
      for (int dy = -(thickness - 1) / 2; dy <= thickness / 2; ++dy)
        for (int dx = -(thickness - 1) / 2; dx <= thickness / 2; ++dx) dot(x + dx, y + dy, c);
    }
  }
  // shape: 0 disc, 1 square, 2 ring, 3 diamond.
  void marker(double cx, double cy, int r, int shape, const Rgb& c) {
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx) {
        const int d2 = dx * dx + dy * dy;
        const bool in = shape == 0   ? d2 <= r * r
                        : shape == 1 ? true
                        : shape == 2 ? d2 <= r * r && d2 >= (r - 2) * (r - 2)
                                     : std::abs(dx) + std::abs(dy) <= r;
        if (in)
          dot(static_cast<int>(std::lround(cx)) + dx, static_cast<int>(std::lround(cy)) + dy, c);
      }
  }
  // Text needs a font; without one the plot keeps its marks and loses its labels.
  void text(int x, int y, const std::string& s, int size = 14,
            OIIO::ImageBufAlgo::TextAlignX align = OIIO::ImageBufAlgo::TextAlignX::Left) {
    if (!OIIO::ImageBufAlgo::render_text(buf_, x, y, s, size, font_,
                                         OIIO::cspan<float>(kBlack.c, 3), align))
      (void)buf_.geterror();
  }
  // Encoded in memory, then written and checked by atomic_file (OpenImageIO's file writer does not
  // report a full disk).
  void write(const fs::path& file) {
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput proxy(bytes);
    buf_.set_write_ioproxy(&proxy);
    if (!buf_.write("trade.png", OIIO::TypeDesc::UINT8))
      throw Error(file.string() + ": " + buf_.geterror());
    buf_.set_write_ioproxy(nullptr);
    writeFileAtomically(file, std::string(bytes.begin(), bytes.end()));
  }

 private:
  ImageBuf buf_;
  std::string font_;
};

// Maps log10(seconds) and rmse to pixels of the plot area.
struct PlotAxes {
  double lx0, lx1, y1;  // y from 0 to y1
  int left = 90, right = 870, top = 50, bottom = 490;
  double x(double seconds) const {
    return left + (std::log10(std::max(seconds, 1e-9)) - lx0) / (lx1 - lx0) * (right - left);
  }
  double y(double rmse) const { return bottom - rmse / y1 * (bottom - top); }
};

PlotAxes plotAxes(const std::vector<Result>& results) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, e = 0.0;
  for (const Result& r : results) {
    const double l = std::log10(std::max(r.seconds, 1e-9));
    lo = std::min(lo, l), hi = std::max(hi, l), e = std::max(e, r.rmse);
  }
  const double pad = std::max(0.08 * (hi - lo), 0.1);
  return PlotAxes{lo - pad, hi + pad, e > 0.0 ? 1.1 * e : 1.0};
}

void drawAxes(Canvas& canvas, const PlotAxes& a) {
  // 1, 2, 5 per decade; every digit when the axis spans less than a decade and a half.
  const std::vector<int> mantissas =
      a.lx1 - a.lx0 < 1.5 ? std::vector<int>{1, 2, 3, 4, 5, 6, 7, 8, 9} : std::vector<int>{1, 2, 5};
  double lastLabel = -1e9;
  for (int d = static_cast<int>(std::floor(a.lx0)); d <= static_cast<int>(std::ceil(a.lx1)); ++d)
    for (int m : mantissas) {
      const double seconds = m * std::pow(10.0, d), l = std::log10(seconds);
      if (l < a.lx0 || l > a.lx1) continue;
      canvas.line(a.x(seconds), a.top, a.x(seconds), a.bottom, kGrey);
      if (a.x(seconds) - lastLabel < 48) continue;  // labels must not overlap
      lastLabel = a.x(seconds);
      canvas.text(static_cast<int>(a.x(seconds)), a.bottom + 20, formatNumber(seconds), 13,
                  OIIO::ImageBufAlgo::TextAlignX::Center);
    }
  const double raw = a.y1 / 5.0, decade = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw <= decade       ? decade
                      : raw <= 2 * decade ? 2 * decade
                      : raw <= 5 * decade ? 5 * decade
                                          : 10 * decade;
  for (int i = 0; i * step <= a.y1; ++i) {
    const double v = i * step;
    canvas.line(a.left, a.y(v), a.right, a.y(v), kGrey);
    canvas.text(a.left - 8, static_cast<int>(a.y(v)) + 5, formatNumber(std::round(v / step) * step),
                13, OIIO::ImageBufAlgo::TextAlignX::Right);
  }
  canvas.line(a.left, a.bottom, a.right, a.bottom, kBlack, 2);
  canvas.line(a.left, a.top, a.left, a.bottom, kBlack, 2);
  canvas.text((a.left + a.right) / 2, a.bottom + 50, "seconds (geometry + render, log scale)", 15,
              OIIO::ImageBufAlgo::TextAlignX::Center);
  canvas.text(12, a.top - 14, "rmse against the reference", 15);
}

void drawLegend(Canvas& canvas, const PlotAxes& a) {
  const int x = a.right - 245, y = a.top + 20;
  canvas.marker(x, y, 5, 0, kBlue), canvas.text(x + 14, y + 5, "hybrid (auto, D or dicing x spp)");
  canvas.marker(x, y + 22, 5, 1, kRed), canvas.text(x + 14, y + 27, "displacement (dicing x spp)");
  canvas.marker(x, y + 44, 6, 3, kBlack), canvas.text(x + 14, y + 49, "reference levels");
  canvas.line(x - 8, y + 66, x + 8, y + 66, kBlack, 2), canvas.text(x + 14, y + 71, "Pareto front");
}

void writePlot(const fs::path& file, const std::vector<Result>& results,
               const std::vector<size_t>& front) {
  Canvas canvas(900, 560);
  const PlotAxes a = plotAxes(results);
  drawAxes(canvas, a);
  for (size_t k = 0; k + 1 < front.size(); ++k)
    canvas.line(a.x(results[front[k]].seconds), a.y(results[front[k]].rmse),
                a.x(results[front[k + 1]].seconds), a.y(results[front[k + 1]].rmse), kBlack, 2);
  for (const Result& r : results) {
    const double x = a.x(r.seconds), y = a.y(r.rmse);
    if (r.config.kind == Kind::Reference)
      canvas.marker(x, y, 6, 3, kBlack);
    else
      canvas.marker(x, y, 5, r.config.kind == Kind::Hybrid ? 0 : 1,
                    r.config.kind == Kind::Hybrid ? kBlue : kRed);
    if (r.config.defaultHybrid)
      canvas.text(static_cast<int>(x) + 8, static_cast<int>(y) - 8, "default", 12);
  }
  for (size_t i : front) canvas.marker(a.x(results[i].seconds), a.y(results[i].rmse), 9, 2, kBlack);
  drawLegend(canvas, a);
  canvas.text(450, 24, "meso trade: error against time", 17,
              OIIO::ImageBufAlgo::TextAlignX::Center);
  canvas.write(file);
}

const Result& defaultHybrid(const std::vector<Result>& results) {
  for (const Result& r : results)
    if (r.config.defaultHybrid) return r;
  throw Error("trade: internal: no default hybrid configuration");
}

double ratio(double a, double b) {
  return b > 0.0 ? a / b : (a > 0.0 ? std::numeric_limits<double>::infinity() : 1.0);
}

// The default hybrid against the cheapest displacement-only configuration at least as accurate
// (equal rmse or better): ratios hybrid / displacement, so < 1 is the hybrid's saving.
std::string summary(const std::vector<Result>& results, const ReferenceStudy& study) {
  const Result& h = defaultHybrid(results);
  const Result* cheapest = nullptr;
  for (const Result& r : results)
    if (r.config.kind == Kind::Displacement && r.rmse <= h.rmse &&
        (!cheapest || r.seconds < cheapest->seconds))
      cheapest = &r;
  char buf[1024];
  int n = std::snprintf(
      buf, sizeof buf,
      "trade: default hybrid (D %g, %g px, %d spp) %.3g s, rmse %.4g, mean %+.3g%%", h.config.D,
      h.config.dicingRate, h.config.spp, h.seconds, h.rmse, h.intensityErrorPct);
  if (cheapest)
    std::snprintf(
        buf + n, sizeof buf - n,
        "; cheapest displacement-only as accurate (dicing %g px, %d spp) %.3g s, rmse %.4g: "
        "speedup %.2fx%s; "
        "hybrid / displacement at equal rmse: time %.3gx, peak memory %.3gx, geometry memory "
        "%.3gx, "
        "micropolygons %.3gx, spp %.3gx",
        cheapest->config.dicingRate, cheapest->config.spp, cheapest->seconds, cheapest->rmse,
        ratio(cheapest->seconds, h.seconds),
        cheapest->seconds < h.seconds ? " (the hybrid is slower)" : "",
        ratio(h.seconds, cheapest->seconds), ratio(h.peakRssMib, cheapest->peakRssMib),
        ratio(h.geometryMib, cheapest->geometryMib),
        ratio(static_cast<double>(h.micropolygons), static_cast<double>(cheapest->micropolygons)),
        ratio(h.config.spp, cheapest->config.spp));
  else
    std::snprintf(buf + n, sizeof buf - n,
                  "; no displacement-only configuration swept is as accurate");
  return std::string(buf) + "\n" + (study.converged ? "trade: " : "trade: WARNING: ") +
         referenceVerdict(study);
}

// --- temporal stability ---

struct Band {
  std::string name;
  float threshold = 0.0f;
  size_t pixels = 0;
  double hybridChange = 0.0, referenceChange = 0.0;  // sums, then means
};

double meanAbsChange(const ImageBuf& a, const ImageBuf& b, int x, int y) {
  float pa[3], pb[3];
  a.getpixel(x, y, pa, 3);
  b.getpixel(x, y, pb, 3);
  return (std::abs(pa[0] - pb[0]) + std::abs(pa[1] - pb[1]) + std::abs(pa[2] - pb[2])) / 3.0;
}

std::vector<Band> temporalBands(const Rendered& hybrid, const Rendered& reference,
                                const TransitionSettings& t, float halfWidth) {
  std::vector<Band> bands = {{"e1", t.e1}, {"e2", t.e2},  {"e3", t.e3},
                             {"e4", t.e4}, {"any", 0.0f}, {"all", 0.0f}};
  for (size_t f = 0; f + 1 < hybrid.films.size(); ++f) {
    const Image& film = hybrid.films[f];
    const int tc = film.channelIndex("T.Y"), zc = film.channelIndex("depth.Z");
    if (tc < 0 || zc < 0) throw Error("trade: the film has no T.Y or depth.Z channel");
    for (int y = 0; y < film.height; ++y)
      for (int x = 0; x < film.width; ++x) {
        if (film.at(x, y, zc) <= 0.0f) continue;  // no surface
        const float T = film.at(x, y, tc);
        const double dh = meanAbsChange(hybrid.beauty[f + 1], hybrid.beauty[f], x, y);
        const double dr = meanAbsChange(reference.beauty[f + 1], reference.beauty[f], x, y);
        bool any = false;
        for (size_t k = 0; k < 4; ++k)
          if (std::abs(T - bands[k].threshold) <= halfWidth) {
            ++bands[k].pixels, bands[k].hybridChange += dh, bands[k].referenceChange += dr,
                any = true;
          }
        if (any) ++bands[4].pixels, bands[4].hybridChange += dh, bands[4].referenceChange += dr;
        ++bands[5].pixels, bands[5].hybridChange += dh, bands[5].referenceChange += dr;
      }
  }
  for (Band& b : bands)
    if (b.pixels > 0)
      b.hybridChange /= static_cast<double>(b.pixels),
          b.referenceChange /= static_cast<double>(b.pixels);
  return bands;
}

void reportTemporal(const std::vector<Band>& bands, const fs::path& file, float halfWidth) {
  std::ostringstream s;
  s << "band,threshold,half_width,pixels,hybrid_mean_abs_change,reference_mean_abs_change,ratio\n";
  std::printf(
      "temporal stability: mean |beauty(f+1) - beauty(f)| in bands |T - e| <= %g of the hybrid\n",
      halfWidth);
  std::printf("  %-5s %9s %10s %12s %12s %8s\n", "band", "threshold", "pixels", "hybrid",
              "reference", "ratio");
  char line[256];
  for (const Band& b : bands) {
    const bool threshold = b.name != "any" && b.name != "all";
    const double ratio = b.referenceChange > 0.0 ? b.hybridChange / b.referenceChange : 0.0;
    const std::string th = threshold ? formatNumber(b.threshold) : "";
    std::snprintf(line, sizeof line, "%s,%s,%g,%zu,%.6g,%.6g,%.4g\n", b.name.c_str(), th.c_str(),
                  halfWidth, b.pixels, b.hybridChange, b.referenceChange, ratio);
    s << line;
    std::printf("  %-5s %9s %10zu %12.5g %12.5g %8.3g\n", b.name.c_str(), th.c_str(), b.pixels,
                b.hybridChange, b.referenceChange, ratio);
  }
  writeText(file, s.str());
}

void progress(const TradeCommandOptions& o, const Result& r, size_t index, size_t count) {
  if (o.quiet) return;
  std::fprintf(
      stderr,
      "meso: trade %zu/%zu %-28s %8.3f s %8.1f MiB %10zu mp  rmse %.5g  mae %.5g  mean %+.3g%%\n",
      index + 1, count, r.config.name.c_str(), r.seconds, r.peakRssMib, r.micropolygons, r.rmse,
      r.meanAbsError, r.intensityErrorPct);
}

}  // namespace

void runTrade(const TradeCommandOptions& o) {
  validate(o);
  Scene scene = loadScene(o.scene);
  if (o.width) scene.camera.width = *o.width;
  if (o.height) scene.camera.height = *o.height;
  if (o.threads) scene.render.threads = *o.threads;
  const bool temporal = o.temporal || o.temporalOnly;
  const std::vector<CameraSettings> cams = cameras(o, scene);
  if (temporal && cams.size() < 2)
    throw Error(
        "--temporal: needs at least two frames: a scene with a [path] and --frames A:B with B > A");
  const std::vector<Configuration> configs = configurations(o, scene);
  for (const Configuration& c : configs)
    sceneFor(scene, c);  // checks every D before rendering anything
  createOutputFolder(o.outDir, "-o");
  for (const char* name : {"trade.csv", "trade.png", "temporal.csv"})
    checkOutputFile(o.outDir / name, "-o");

  const int threads =
      scene.render.threads > 0 ? scene.render.threads : tbb::info::default_concurrency();
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  gTradeInterrupted.store(false);
  std::signal(SIGINT, onTradeInterrupt);
  std::signal(SIGTERM, onTradeInterrupt);
  if (!o.quiet)
    std::fprintf(stderr, "meso: trade: %zu configurations x %zu frame(s) at %dx%d, %d threads\n",
                 configs.size(), cams.size(), scene.camera.width, scene.camera.height, threads);

  bool warnedRss = false;
  const ReferenceCache cache(o.noReferenceCache         ? fs::path()
                             : o.referenceCache.empty() ? ReferenceCache::defaultFolder(scene)
                                                        : o.referenceCache);
  const ReferenceStudy study = convergeReference(scene, o, cams, cache, warnedRss);
  if (!study.converged)
    std::fprintf(stderr, "meso: WARNING: %s\n", referenceVerdict(study).c_str());
  std::vector<Result> results;
  for (size_t k = 0; k < study.levels.size(); ++k) {
    const ReferenceLevel& l = study.levels[k];
    const bool last = k + 1 == study.levels.size();
    const Configuration c{last ? "reference" : "reference_l" + std::to_string(k),
                          Kind::Reference,
                          0.0f,
                          l.spp,
                          l.dicingRate,
                          false};
    Result result{c, l.render.seconds, l.render.peakRssMib, l.render.micropolygons,
                  l.render.geometryMib};
    addErrors(result, l.render.beauty, study.reference().beauty);
    results.push_back(result);
  }
  const Rendered& reference = study.reference();
  Rendered hybrid;
  for (size_t i = 0; i < configs.size(); ++i) {
    const Configuration& c = configs[i];
    const bool keepFilms = temporal && c.defaultHybrid;
    Rendered r = renderConfiguration(scene, c, cams, keepFilms, warnedRss);
    Result result{c, r.seconds, r.peakRssMib, r.micropolygons, r.geometryMib};
    addErrors(result, r.beauty, reference.beauty);
    results.push_back(result);
    progress(o, result, i, configs.size());
    if (keepFilms) hybrid = std::move(r);
  }

  writeText(o.outDir / "trade.csv", csv(results, study));
  writePlot(o.outDir / "trade.png", results, paretoFront(results));
  if (!o.quiet)
    std::fprintf(stderr, "meso: wrote %s and %s\n", (o.outDir / "trade.csv").string().c_str(),
                 (o.outDir / "trade.png").string().c_str());
  std::printf("%s\n", summary(results, study).c_str());
  if (temporal) {
    reportTemporal(temporalBands(hybrid, reference, scene.render.transition, o.band),
                   o.outDir / "temporal.csv", o.band);
    if (!o.quiet)
      std::fprintf(stderr, "meso: wrote %s\n", (o.outDir / "temporal.csv").string().c_str());
  }
}

}  // namespace meso::app
