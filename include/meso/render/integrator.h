// Renders a prepared frame: stratified samples per pixel, TBB over tiles, deterministic per seed.
#pragma once

#include "meso/core/image.h"
#include "meso/render/film_layout.h"
#include "meso/render/render_context.h"

#include <array>
#include <atomic>
#include <cstdint>
#include <exception>
#include <optional>

namespace meso {

// A rectangle of the camera's image in pixels: columns [x0, x1), rows [y0, y1).
struct PixelWindow {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
};

struct RenderOptions {
  int spp = 4;
  uint64_t seed = 0;
  bool progress = true;      // progress bar on stderr (drawn only when stderr is a terminal)
  bool falseColour = false;  // beauty = algorithm colours (Figure 4) instead of shading
  // Polled once per tile; when it becomes true the frame stops and renderFrame throws Interrupted.
  const std::atomic<bool>* cancel = nullptr;
  // The bump renderer filters its slopes over each sample's footprint with Schilling's pyramids;
  // false: point-sampled Blinn bump mapping (aliases when the relief is finer than a pixel).
  bool filterBump = true;
  // Colour textures are filtered over each sample's footprint (MIP-mapped lookups); false: the
  // texel under the sample, bilinear at the finest level (a reference that many samples filter).
  bool filterTextures = true;
  // Camera rays only: each sample's closest hit is found with Embree and nothing else is done (no
  // shading, no shadow rays; beauty is black, depth.Z as usual). The cost of tracing exactly the
  // frame's rays against its geometry: the baseline tools/bench_frame measures renderers against.
  bool traceOnly = false;
  // With traceOnly: also each hit's shadow rays towards the lights (when the context has shadows),
  // from the hit moved off its triangle along Embree's geometric normal: every ray the shaded
  // frame traces, without its shading (tools/bench_frame's trace_all).
  bool traceShadowRays = false;
  // Only this window of the image (within it); the film is the window's size and its pixel (x, y)
  // is the whole image's (x0 + x, y0 + y), the same bits (samples depend on the image pixel).
  std::optional<PixelWindow> window = std::nullopt;
};

// Thrown by renderFrame when RenderOptions::cancel was set: the frame is incomplete.
struct Interrupted : std::exception {
  const char* what() const noexcept override { return "interrupted"; }
};

// Who shaded the samples (--stats "sample_shares"): a sample that misses is background; one on an
// object without relief is smooth; one on relief counts for the algorithm asked for, or, with auto,
// is split by the transition weights of its finest visible level (DESIGN.md section 3): brdf,
// redistribution (1 - brdf) (1 - disp) and displacement (1 - brdf) disp.
enum class SampleRenderer { Background, Smooth, Brdf, Bump, Redistribution, Displacement };
inline constexpr int kSampleRenderers = 6;
inline constexpr std::array<const char*, kSampleRenderers> kSampleRendererNames = {
    "background", "smooth", "brdf", "bump", "redistribution", "displacement"};
// Samples are counted in units of 1 / kShareUnit (integers: the sums are exact in any order).
inline constexpr int64_t kShareUnit = 1 << 16;

struct RenderCounters {
  std::atomic<int64_t> rays{0};
  // Per SampleRenderer, in units of 1 / kShareUnit samples; they sum to rays * kShareUnit (none
  // are counted with RenderOptions::traceOnly).
  std::array<std::atomic<int64_t>, kSampleRenderers> shares{};
  // Film values that came out NaN or infinite and were written as 0 instead: always 0 unless meso
  // has a bug (the renderer's own check; the CLI warns and --stats reports it).
  std::atomic<int64_t> nonFinite{0};
};

// The film's layers are FilmLayout's (film_layout.h): beauty, depth, shading normal, algorithm
// colours and T.
// Every pixel depends only on (seed, pixel, sample index), so any thread count gives the same bits.
Image renderFrame(const RenderContext& ctx, const RenderOptions& options, RenderCounters& counters);

}  // namespace meso
