// `meso trade`: Becker & Max 1993's promise, measured. The paper's D (our render.transition.D, its c)
// trades accuracy for speed; this command renders a converged full-displacement reference and then
// every configuration of the hybrid (D x spp) and of displacement alone (dicing rate x spp), and
// reports seconds, peak memory, micropolygons and image error against the reference.
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
// - micropolygons: the most displaced micropolygons of any frame.
// - errors: of the beauty R, G, B against the reference with OpenImageIO's ImageBufAlgo::compare
//   (mean absolute and RMS difference over pixels and channels) and computePixelStats
//   (mean_intensity_error_pct = 100 |mean(img) - mean(ref)| / mean(ref), means over R, G, B),
//   averaged over the frames.
// Temporal stability (--temporal): for consecutive frames f, f+1 of the default hybrid and of the
// reference, the mean over R, G, B of |beauty(f+1) - beauty(f)| over the pixels whose T.Y in the
// hybrid's frame f lies within --band of e1, e2, e3 or e4 (pixels where no surface was hit are left
// out), pooled over the frame pairs.
#include "trade_command.h"

#include "render_command.h"

#include "meso/core/atomic_file.h"
#include "meso/core/error.h"
#include "meso/core/timer.h"
#include "meso/render/integrator.h"
#include "meso/render/render_context.h"
#include "meso/render/transition.h"
#include "meso/scene/camera_path.h"
#include "meso/scene/scene_parser.h"

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
  double meanAbsError = 0.0, rmse = 0.0, intensityErrorPct = 0.0;
};

// One configuration's frames: beauty as OpenImageIO buffers; whole films only when kept.
struct Rendered {
  double seconds = 0.0;
  double peakRssMib = 0.0;
  size_t micropolygons = 0;
  std::vector<ImageBuf> beauty;
  std::vector<Image> films;
};

const char* algorithmName(Kind k) { return k == Kind::Hybrid ? "auto" : "displacement"; }

std::string formatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// --- options ---

std::pair<int, int> parseFrameRange(const std::string& text, int count) {
  if (text.empty()) return {0, count - 1};
  const size_t colon = text.find(':');
  try {
    const int a = std::stoi(text.substr(0, colon));
    const int b = colon == std::string::npos ? a
                  : (colon + 1 < text.size() ? std::stoi(text.substr(colon + 1)) : count - 1);
    if (a < 0 || b < a || b >= count) throw std::out_of_range("range");
    return {a, b};
  } catch (const std::logic_error&) {
    throw Error("--frames: expected A:B with 0 <= A <= B < " + std::to_string(count) + ", got \"" + text + "\"");
  }
}

template <class T>
void checkValues(const std::vector<T>& values, const char* option, double lo, double hi) {
  if (values.empty()) throw Error(std::string(option) + ": needs at least one value");
  for (T v : values)
    if (!std::isfinite(static_cast<double>(v)) || v < lo || v > hi)
      throw Error(std::string(option) + ": " + formatNumber(static_cast<double>(v)) + " is outside [" +
                  formatNumber(lo) + ", " + formatNumber(hi) + "]");
}

void validate(const TradeCommandOptions& o) {
  checkValues(std::vector<int>{o.referenceSpp}, "--reference-spp", 1, 65536);
  checkValues(std::vector<float>{o.referenceDicingRate}, "--reference-dicing-rate", 0.01, 1000);
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
      throw Error(scene.file.string() + ": path: --frames needs a [path] with keyframes in the scene");
    return {scene.camera};
  }
  const CameraPath path(scene.path.keys);
  const auto [first, last] = parseFrameRange(o.frames, scene.path.frames);
  std::vector<CameraSettings> result;
  for (int f = first; f <= last; ++f) result.push_back(path.frame(f, scene.path.frames, scene.camera));
  return result;
}

std::vector<Configuration> configurations(const TradeCommandOptions& o, const Scene& scene) {
  std::vector<Configuration> list;
  list.push_back({"reference", Kind::Reference, 0.0f, o.referenceSpp, o.referenceDicingRate, false});
  const float sceneD = scene.render.transition.D;
  const int sceneSpp = scene.camera.spp;
  const auto hybrid = [&](float D, int spp) {
    return Configuration{"hybrid_D" + formatNumber(D) + "_spp" + std::to_string(spp), Kind::Hybrid, D, spp,
                         scene.render.dicingRate, D == sceneD && spp == sceneSpp};
  };
  bool haveDefault = false;
  if (!o.temporalOnly)
    for (float D : o.dValues)
      for (int spp : o.sppValues) {
        list.push_back(hybrid(D, spp));
        haveDefault = haveDefault || list.back().defaultHybrid;
      }
  if (!haveDefault) list.push_back(hybrid(sceneD, sceneSpp));  // the summary's configuration
  if (!o.temporalOnly)
    for (float rate : o.dicingRates)
      for (int spp : o.sppValues)
        list.push_back({"displacement_r" + formatNumber(rate) + "_spp" + std::to_string(spp), Kind::Displacement,
                        0.0f, spp, rate, false});
  return list;
}

// --- rendering ---

// Returns freed heap to the system and resets VmHWM; false where /proc/self/clear_refs is not writable.
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

Rendered renderConfiguration(const Scene& base, const Configuration& c, const std::vector<CameraSettings>& cams,
                             bool keepFilms, bool& warnedRss) {
  const Scene scene = sceneFor(base, c);
  Rendered out;
  if (!resetPeakRss() && !warnedRss) {
    std::fprintf(stderr, "meso: warning: cannot reset the peak RSS (/proc/self/clear_refs); peak_rss_mib is the "
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
    out.beauty.push_back(beautyBuffer(film));
    if (keepFilms) out.films.push_back(std::move(film));
  }
  out.peakRssMib = peakRssMib();
  for (const std::string& w : ctx.warnings) std::fprintf(stderr, "meso: warning: %s: %s\n", c.name.c_str(), w.c_str());
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

void addErrors(Result& r, const std::vector<ImageBuf>& images, const std::vector<ImageBuf>& reference) {
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

// --- outputs ---

void writeText(const fs::path& file, const std::string& text) {
  writeAtomically(file, [&](const fs::path& tmp) {
    std::ofstream out(tmp);
    out << text;
    if (!out.flush()) throw Error(file.string() + ": cannot write");
  });
}

std::string csv(const std::vector<Result>& results) {
  std::ostringstream s;
  s << "name,algorithm,D,spp,dicing_rate,seconds,peak_rss_mib,micropolygons,mean_abs_error,rmse,"
       "mean_intensity_error_pct\n";
  char line[512];
  for (const Result& r : results) {
    const Configuration& c = r.config;
    // D is left empty where the algorithm does not use it (displacement alone).
    const std::string D = c.kind == Kind::Hybrid ? formatNumber(c.D) : "";
    std::snprintf(line, sizeof line, "%s,%s,%s,%d,%g,%.6g,%.1f,%zu,%.6g,%.6g,%.6g\n", c.name.c_str(),
                  algorithmName(c.kind), D.c_str(), c.spp, c.dicingRate, r.seconds, r.peakRssMib, r.micropolygons,
                  r.meanAbsError, r.rmse, r.intensityErrorPct);
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
    if (x >= 0 && y >= 0 && x < buf_.spec().width && y < buf_.spec().height) buf_.setpixel(x, y, c.c, 3);
  }
  void line(double x0, double y0, double x1, double y1, const Rgb& c, int thickness = 1) {
    const int steps = static_cast<int>(std::max(std::abs(x1 - x0), std::abs(y1 - y0))) + 1;
    for (int i = 0; i <= steps; ++i) {
      const double t = static_cast<double>(i) / steps;
      const int x = static_cast<int>(std::lround(x0 + t * (x1 - x0))), y = static_cast<int>(std::lround(y0 + t * (y1 - y0)));
      for (int dy = -(thickness - 1) / 2; dy <= thickness / 2; ++dy)
        for (int dx = -(thickness - 1) / 2; dx <= thickness / 2; ++dx) dot(x + dx, y + dy, c);
    }
  }
  // shape: 0 disc, 1 square, 2 ring, 3 diamond.
  void marker(double cx, double cy, int r, int shape, const Rgb& c) {
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx) {
        const int d2 = dx * dx + dy * dy;
        const bool in = shape == 0 ? d2 <= r * r
                        : shape == 1 ? true
                        : shape == 2 ? d2 <= r * r && d2 >= (r - 2) * (r - 2)
                                     : std::abs(dx) + std::abs(dy) <= r;
        if (in) dot(static_cast<int>(std::lround(cx)) + dx, static_cast<int>(std::lround(cy)) + dy, c);
      }
  }
  // Text needs a font; without one the plot keeps its marks and loses its labels.
  void text(int x, int y, const std::string& s, int size = 14, OIIO::ImageBufAlgo::TextAlignX align = OIIO::ImageBufAlgo::TextAlignX::Left) {
    if (!OIIO::ImageBufAlgo::render_text(buf_, x, y, s, size, font_, OIIO::cspan<float>(kBlack.c, 3), align))
      (void)buf_.geterror();
  }
  void write(const fs::path& file) {
    writeAtomically(file, [&](const fs::path& tmp) {
      if (!buf_.write(tmp.string(), OIIO::TypeDesc::UINT8)) throw Error(file.string() + ": " + buf_.geterror());
    });
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
  const std::vector<int> mantissas = a.lx1 - a.lx0 < 1.5 ? std::vector<int>{1, 2, 3, 4, 5, 6, 7, 8, 9}
                                                         : std::vector<int>{1, 2, 5};
  double lastLabel = -1e9;
  for (int d = static_cast<int>(std::floor(a.lx0)); d <= static_cast<int>(std::ceil(a.lx1)); ++d)
    for (int m : mantissas) {
      const double seconds = m * std::pow(10.0, d), l = std::log10(seconds);
      if (l < a.lx0 || l > a.lx1) continue;
      canvas.line(a.x(seconds), a.top, a.x(seconds), a.bottom, kGrey);
      if (a.x(seconds) - lastLabel < 48) continue;  // labels must not overlap
      lastLabel = a.x(seconds);
      canvas.text(static_cast<int>(a.x(seconds)), a.bottom + 20, formatNumber(seconds), 13, OIIO::ImageBufAlgo::TextAlignX::Center);
    }
  const double raw = a.y1 / 5.0, decade = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw <= decade ? decade : raw <= 2 * decade ? 2 * decade : raw <= 5 * decade ? 5 * decade : 10 * decade;
  for (int i = 0; i * step <= a.y1; ++i) {
    const double v = i * step;
    canvas.line(a.left, a.y(v), a.right, a.y(v), kGrey);
    canvas.text(a.left - 8, static_cast<int>(a.y(v)) + 5, formatNumber(std::round(v / step) * step), 13,
                OIIO::ImageBufAlgo::TextAlignX::Right);
  }
  canvas.line(a.left, a.bottom, a.right, a.bottom, kBlack, 2);
  canvas.line(a.left, a.top, a.left, a.bottom, kBlack, 2);
  canvas.text((a.left + a.right) / 2, a.bottom + 50, "seconds (geometry + render, log scale)", 15, OIIO::ImageBufAlgo::TextAlignX::Center);
  canvas.text(12, a.top - 14, "rmse against the reference", 15);
}

void drawLegend(Canvas& canvas, const PlotAxes& a) {
  const int x = a.right - 210, y = a.top + 20;
  canvas.marker(x, y, 5, 0, kBlue), canvas.text(x + 14, y + 5, "hybrid (auto, D x spp)");
  canvas.marker(x, y + 22, 5, 1, kRed), canvas.text(x + 14, y + 27, "displacement (dicing x spp)");
  canvas.marker(x, y + 44, 6, 3, kBlack), canvas.text(x + 14, y + 49, "reference");
  canvas.line(x - 8, y + 66, x + 8, y + 66, kBlack, 2), canvas.text(x + 14, y + 71, "Pareto front");
}

void writePlot(const fs::path& file, const std::vector<Result>& results, const std::vector<size_t>& front) {
  Canvas canvas(900, 560);
  const PlotAxes a = plotAxes(results);
  drawAxes(canvas, a);
  for (size_t k = 0; k + 1 < front.size(); ++k)
    canvas.line(a.x(results[front[k]].seconds), a.y(results[front[k]].rmse), a.x(results[front[k + 1]].seconds),
                a.y(results[front[k + 1]].rmse), kBlack, 2);
  for (const Result& r : results) {
    const double x = a.x(r.seconds), y = a.y(r.rmse);
    if (r.config.kind == Kind::Reference) canvas.marker(x, y, 6, 3, kBlack);
    else canvas.marker(x, y, 5, r.config.kind == Kind::Hybrid ? 0 : 1, r.config.kind == Kind::Hybrid ? kBlue : kRed);
    if (r.config.defaultHybrid) canvas.text(static_cast<int>(x) + 8, static_cast<int>(y) - 8, "default", 12);
  }
  for (size_t i : front) canvas.marker(a.x(results[i].seconds), a.y(results[i].rmse), 9, 2, kBlack);
  drawLegend(canvas, a);
  canvas.text(450, 24, "meso trade: error against time", 17, OIIO::ImageBufAlgo::TextAlignX::Center);
  canvas.write(file);
}

const Result& defaultHybrid(const std::vector<Result>& results) {
  for (const Result& r : results)
    if (r.config.defaultHybrid) return r;
  throw Error("trade: internal: no default hybrid configuration");
}

std::string summary(const std::vector<Result>& results) {
  const Result& h = defaultHybrid(results);
  const Result* cheapest = nullptr;
  for (const Result& r : results)
    if (r.config.kind == Kind::Displacement && r.rmse <= h.rmse && (!cheapest || r.seconds < cheapest->seconds))
      cheapest = &r;
  char buf[512];
  if (cheapest)
    std::snprintf(buf, sizeof buf,
                  "trade: default hybrid (D %g, %d spp) %.3g s, rmse %.4g; cheapest displacement-only as accurate "
                  "(dicing %g px, %d spp) %.3g s, rmse %.4g: speedup %.2fx%s",
                  h.config.D, h.config.spp, h.seconds, h.rmse, cheapest->config.dicingRate, cheapest->config.spp,
                  cheapest->seconds, cheapest->rmse, cheapest->seconds / std::max(h.seconds, 1e-9),
                  cheapest->seconds < h.seconds ? " (the hybrid is slower)" : "");
  else
    std::snprintf(buf, sizeof buf,
                  "trade: default hybrid (D %g, %d spp) %.3g s, rmse %.4g; no displacement-only configuration swept "
                  "is as accurate",
                  h.config.D, h.config.spp, h.seconds, h.rmse);
  return buf;
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

std::vector<Band> temporalBands(const Rendered& hybrid, const Rendered& reference, const TransitionSettings& t,
                                float halfWidth) {
  std::vector<Band> bands = {{"e1", t.e1}, {"e2", t.e2}, {"e3", t.e3}, {"e4", t.e4}, {"any", 0.0f}, {"all", 0.0f}};
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
            ++bands[k].pixels, bands[k].hybridChange += dh, bands[k].referenceChange += dr, any = true;
          }
        if (any) ++bands[4].pixels, bands[4].hybridChange += dh, bands[4].referenceChange += dr;
        ++bands[5].pixels, bands[5].hybridChange += dh, bands[5].referenceChange += dr;
      }
  }
  for (Band& b : bands)
    if (b.pixels > 0) b.hybridChange /= static_cast<double>(b.pixels), b.referenceChange /= static_cast<double>(b.pixels);
  return bands;
}

void reportTemporal(const std::vector<Band>& bands, const fs::path& file, float halfWidth) {
  std::ostringstream s;
  s << "band,threshold,half_width,pixels,hybrid_mean_abs_change,reference_mean_abs_change,ratio\n";
  std::printf("temporal stability: mean |beauty(f+1) - beauty(f)| in bands |T - e| <= %g of the hybrid\n", halfWidth);
  std::printf("  %-5s %9s %10s %12s %12s %8s\n", "band", "threshold", "pixels", "hybrid", "reference", "ratio");
  char line[256];
  for (const Band& b : bands) {
    const bool threshold = b.name != "any" && b.name != "all";
    const double ratio = b.referenceChange > 0.0 ? b.hybridChange / b.referenceChange : 0.0;
    const std::string th = threshold ? formatNumber(b.threshold) : "";
    std::snprintf(line, sizeof line, "%s,%s,%g,%zu,%.6g,%.6g,%.4g\n", b.name.c_str(), th.c_str(), halfWidth, b.pixels,
                  b.hybridChange, b.referenceChange, ratio);
    s << line;
    std::printf("  %-5s %9s %10zu %12.5g %12.5g %8.3g\n", b.name.c_str(), th.c_str(), b.pixels, b.hybridChange,
                b.referenceChange, ratio);
  }
  writeText(file, s.str());
}

void progress(const TradeCommandOptions& o, const Result& r, size_t index, size_t count) {
  if (o.quiet) return;
  std::fprintf(stderr, "meso: trade %zu/%zu %-28s %8.3f s %8.1f MiB %10zu mp  rmse %.5g  mae %.5g  mean %+.3g%%\n",
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
    throw Error("--temporal: needs at least two frames: a scene with a [path] and --frames A:B with B > A");
  const std::vector<Configuration> configs = configurations(o, scene);
  for (const Configuration& c : configs) sceneFor(scene, c);  // checks every D before rendering anything
  fs::create_directories(o.outDir);

  const int threads = scene.render.threads > 0 ? scene.render.threads : tbb::info::default_concurrency();
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  gTradeInterrupted.store(false);
  std::signal(SIGINT, onTradeInterrupt);
  std::signal(SIGTERM, onTradeInterrupt);
  if (!o.quiet)
    std::fprintf(stderr, "meso: trade: %zu configurations x %zu frame(s) at %dx%d, %d threads\n", configs.size(),
                 cams.size(), scene.camera.width, scene.camera.height, threads);

  bool warnedRss = false;
  std::vector<Result> results;
  Rendered reference, hybrid;
  for (size_t i = 0; i < configs.size(); ++i) {
    const Configuration& c = configs[i];
    const bool keepFilms = temporal && c.defaultHybrid;
    Rendered r = renderConfiguration(scene, c, cams, keepFilms, warnedRss);
    Result result{c, r.seconds, r.peakRssMib, r.micropolygons};
    addErrors(result, r.beauty, i == 0 ? r.beauty : reference.beauty);
    results.push_back(result);
    progress(o, result, i, configs.size());
    if (i == 0) reference = std::move(r);
    else if (keepFilms) hybrid = std::move(r);
  }

  writeText(o.outDir / "trade.csv", csv(results));
  writePlot(o.outDir / "trade.png", results, paretoFront(results));
  if (!o.quiet)
    std::fprintf(stderr, "meso: wrote %s and %s\n", (o.outDir / "trade.csv").string().c_str(),
                 (o.outDir / "trade.png").string().c_str());
  std::printf("%s\n", summary(results).c_str());
  if (temporal) {
    reportTemporal(temporalBands(hybrid, reference, scene.render.transition, o.band), o.outDir / "temporal.csv", o.band);
    if (!o.quiet) std::fprintf(stderr, "meso: wrote %s\n", (o.outDir / "temporal.csv").string().c_str());
  }
}

}  // namespace meso::app
