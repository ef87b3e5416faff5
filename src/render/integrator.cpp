#include "meso/render/integrator.h"

#include "meso/core/error.h"
#include "meso/core/progress.h"
#include "meso/core/rng.h"
#include "meso/render/environment_map.h"
#include "meso/render/film_layout.h"
#include "meso/render/shadow_rays.h"
#include "meso/render/surface_shader.h"
#include "meso/render/transition.h"

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace meso {
namespace {

constexpr int kTileSize = 16;

using Pixel = glm::ivec2;

// The paper's Figure 4 look: the algorithm colours, shaded by the beauty's brightness so the shapes
// stay readable.
Vec3 falseColour(const Vec3& beauty, const Vec3& algorithm) {
  const float lum = std::min(1.0f, luminance(beauty));
  return algorithm * (0.25f + 0.75f * lum);
}

struct PixelSum {
  Vec3 colour{0.0f};
  Vec3 algorithm{0.0f};
  Vec3 normal{0.0f};
  float depth = 0.0f;
  float T = 0.0f;
  int hits = 0;
};

using ShareCounts = std::array<int64_t, kSampleRenderers>;

void addShare(ShareCounts& shares, SampleRenderer r, float weight) {
  shares[static_cast<int>(r)] += static_cast<int64_t>(std::lround(weight * kShareUnit));
}

// One sample's share of each renderer (see SampleRenderer); they add up to kShareUnit.
void countSample(const RenderContext& ctx, const PreparedObject& object, float T,
                 ShareCounts& shares) {
  if (ctx.reliefs[object.material].levels.empty())
    return addShare(shares, SampleRenderer::Smooth, 1);
  switch (ctx.algorithm) {
    case Algorithm::Brdf:
      return addShare(shares, SampleRenderer::Brdf, 1.0f);
    case Algorithm::Bump:
      return addShare(shares, SampleRenderer::Bump, 1.0f);
    case Algorithm::Redistribution:
      return addShare(shares, SampleRenderer::Redistribution, 1.0f);
    case Algorithm::Displacement:
      return addShare(shares, SampleRenderer::Displacement, 1.0f);
    case Algorithm::Auto:
      break;
  }
  const TransitionWeights w = transitionWeights(T, ctx.scene->render.transition);
  const int64_t brdf = std::lround(w.brdf * kShareUnit);
  const int64_t disp = std::lround(w.redistribution * w.disp * kShareUnit);
  shares[static_cast<int>(SampleRenderer::Brdf)] += brdf;
  shares[static_cast<int>(SampleRenderer::Displacement)] += disp;
  shares[static_cast<int>(SampleRenderer::Redistribution)] += kShareUnit - brdf - disp;
}

// The hit triangle's unit normal from Embree (either orientation: its users turn it towards the
// eye), or `fallback` for a degenerate triangle.
Vec3 facetNormal(const RayHit& hit, const Vec3& fallback) {
  const float length = glm::length(hit.Ng);
  return length > 0.0f && std::isfinite(length) ? hit.Ng / length : fallback;
}

// What a camera sample's ray found, before shading: the hit, and for a hit the limit surface at
// its patch coordinates (position, frame and normal come from there, never from the triangle;
// Chan 2002).
struct SampleHit {
  RayHit hit;
  bool found = false;
  SurfacePoint sp;
  Vec3 facet{0.0f};   // the hit triangle's unit normal
  Vec3 limitP{0.0f};  // the limit surface's point (sp.P is moved to the raised hit when displaced)
  float lengthPerU = 0.0f;  // the object's UvSpeed at the hit (0: none), as the tessellator's T
};

void evaluateHit(const RenderContext& ctx, const Ray& ray, SampleHit& s) {
  const PreparedObject& object = ctx.objects[s.hit.mesh];
  // A grid hit knows its face and patch coordinates; other triangles read the mesh's arrays.
  const bool fromGrid = s.hit.face >= 0;
  const int face = fromGrid ? s.hit.face : object.mesh.triangleFace[s.hit.triangle];
  const Vec2 st = fromGrid ? s.hit.st : object.mesh.patchCoords(s.hit.triangle, s.hit.b1, s.hit.b2);
  s.sp = object.surface.evaluate(face, st);
  s.lengthPerU = object.uvSpeed.at(face, st);
  s.facet = facetNormal(s.hit, s.sp.N);
  s.limitP = s.sp.P;
  if (object.displaced)
    s.sp.P = ray.origin + s.hit.t * ray.direction;  // lights see the raised point, not the limit
}

// Shades one camera sample from what its ray found and the lights' visibility from its hit.
// footprintScale: the bump filter's footprint (0: off); pixelScale: a sample's share of the pixel,
// over which colour textures are filtered (0: point lookups).
void shadeSample(const RenderContext& ctx, const Ray& ray, float fx, float fy, float footprintScale,
                 float pixelScale, const SampleHit& s, std::span<const Light> lights,
                 const LightShadows& shadows, PixelSum& sum, ShareCounts& shares) {
  if (!s.found) {  // the environment where there is one, else render.background
    sum.colour +=
        ctx.environment ? ctx.environment->radiance(ray.direction) : ctx.scene->render.background;
    addShare(shares, SampleRenderer::Background, 1.0f);
    return;
  }
  const PreparedObject& object = ctx.objects[s.hit.mesh];
  Footprint footprint;
  if (ctx.algorithm == Algorithm::Bump && footprintScale > 0.0f)  // only the bump renderer filters
    footprint = footprintAt(s.sp, ctx.camera.generateRay(fx + 1.0f, fy),
                            ctx.camera.generateRay(fx, fy + 1.0f), footprintScale);
  std::optional<Reflectance> textured;
  if (ctx.textured(object.material))
    textured = textureReflectance(
        ctx, object.material, s.sp.uv,
        pixelScale > 0.0f ? footprintAt(s.sp, ctx.camera.generateRay(fx + 1.0f, fy),
                                        ctx.camera.generateRay(fx, fy + 1.0f), pixelScale)
                          : Footprint{});
  const ShadeResult r =
      shadeSurface(ctx, object, s.sp, -ray.direction, lights,
                   ctx.facetNormals && object.displaced ? &s.facet : nullptr, &footprint, &s.limitP,
                   ctx.shadows ? &shadows : nullptr, textured ? &*textured : nullptr, s.lengthPerU);
  sum.colour += r.colour;
  sum.algorithm += r.algorithm;
  sum.normal += r.normal;
  sum.T += r.T;
  sum.depth += s.hit.t;
  sum.hits += 1;
  countSample(ctx, object, r.T, shares);
}

// Writes a pixel's means into FilmLayout's channels; a value that is not finite is written as 0
// and counted.
void writePixel(const PixelSum& sum, int spp, bool falseColourBeauty, int x, int y, Image& film,
                int64_t& nonFinite) {
  const float inv = 1.0f / static_cast<float>(spp);
  const float invHits = sum.hits > 0 ? 1.0f / static_cast<float>(sum.hits) : 0.0f;
  Vec3 beauty = sum.colour * inv;
  const Vec3 algorithm = sum.algorithm * inv;
  if (falseColourBeauty) beauty = falseColour(beauty, algorithm);
  std::array<float, FilmLayout::kChannels> values{};
  values[FilmLayout::R] = beauty.r, values[FilmLayout::G] = beauty.g;
  values[FilmLayout::B] = beauty.b;
  values[FilmLayout::DepthZ] = sum.depth * invHits;
  values[FilmLayout::NormalX] = sum.normal.x * invHits;
  values[FilmLayout::NormalY] = sum.normal.y * invHits;
  values[FilmLayout::NormalZ] = sum.normal.z * invHits;
  values[FilmLayout::AlgorithmR] = algorithm.r, values[FilmLayout::AlgorithmG] = algorithm.g;
  values[FilmLayout::AlgorithmB] = algorithm.b;
  values[FilmLayout::T] = sum.T * invHits;
  for (int c = 0; c < FilmLayout::kChannels; ++c) {
    const bool finite = std::isfinite(values[c]);
    nonFinite += !finite;
    film.at(x, y, c) = finite ? values[c] : 0.0f;
  }
}

// Camera samples are traced and shaded in chunks of whole pixels, about this many samples each:
// the chunk's camera rays go to Embree as one coherent stream, and so do its shadow rays towards
// each light (RayScene's stream queries), which Embree traces in packets.
constexpr int kChunkSamples = 1024;

// The buffers of one chunk, reused from chunk to chunk of a tile range.
struct Chunk {
  std::vector<Ray> rays;
  std::vector<Vec2> film;  // each sample's film position
  std::vector<SampleHit> hits;
  std::vector<uint8_t> found;
  std::vector<RayHit> rayHits;
  std::vector<LightShadows> shadows;
  std::vector<Ray> shadowRays;
  std::vector<uint32_t> shadowOf;  // the sample of each shadow ray
  std::vector<uint8_t> occluded;
  std::vector<Vec3> starts;  // each hit's shadow-ray start
  // With an environment: each sample's lights (the scene's, then the environment's samples),
  // lightsPerSample of them per sample; empty without one (every sample has the scene's lights).
  std::vector<Light> lights;
  size_t lightsPerSample = 0;
  std::span<const Light> lightsOf(const RenderContext& ctx, size_t s) const {
    if (lights.empty()) return ctx.scene->lights;
    return std::span<const Light>(lights).subspan(s * lightsPerSample, lightsPerSample);
  }
};

// Each hit's lights when the scene has an environment: the scene's lights, then
// render.light_samples directional lights drawn for the sample (environmentLights).
void sampleChunkLights(const RenderContext& ctx, uint64_t seed, bool traceOnly, Chunk& chunk) {
  chunk.lights.clear();
  if (!ctx.environment) return;
  const size_t n = chunk.rays.size(), m = ctx.lightsPerSample();
  const size_t finite = ctx.scene->lights.size();
  chunk.lightsPerSample = m;
  chunk.lights.resize(n * m);
  for (size_t s = 0; s < n; ++s) {
    if (!chunk.hits[s].found) continue;
    const std::span<Light> lights = std::span<Light>(chunk.lights).subspan(s * m, m);
    std::copy(ctx.scene->lights.begin(), ctx.scene->lights.end(), lights.begin());
    environmentLights(*ctx.environment, environmentSampleKey(chunk.film[s], seed),
                      lights.subspan(finite));
    // The surface is opaque: a direction below the macro surface's horizon (its limit normal on
    // the viewer's side) lights nothing there, relief or not, and needs no shadow ray.
    if (traceOnly) continue;
    Vec3 n = chunk.hits[s].sp.N;
    if (glm::dot(n, chunk.rays[s].direction) > 0.0f) n = -n;
    for (Light& l : lights.subspan(finite))
      if (!(glm::dot(l.direction, n) < 0.0f)) l.colour = Vec3(0.0f);
  }
}

// The camera rays of `pixels`, spp each, pixel by pixel, each pixel's jitter drawn by its own
// generator (so the samples do not depend on how pixels are grouped into tiles and chunks).
void generateChunk(const RenderContext& ctx, const RenderOptions& options, int width,
                   std::span<const Pixel> pixels, Chunk& chunk) {
  const int spp = options.spp;
  const int cols = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(spp))));
  const int rows = (spp + cols - 1) / cols;
  chunk.rays.clear();
  chunk.film.clear();
  for (const Pixel& p : pixels) {
    Rng rng(options.seed,
            static_cast<uint64_t>(p.y) * static_cast<uint64_t>(width) + static_cast<uint64_t>(p.x));
    for (int i = 0; i < spp; ++i) {
      // Jittered stratum (i % cols, i / cols) of a cols x rows grid over the pixel.
      const float fx = (static_cast<float>(i % cols) + rng.uniform()) / static_cast<float>(cols);
      const float fy = (static_cast<float>(i / cols) + rng.uniform()) / static_cast<float>(rows);
      const Vec2 f(static_cast<float>(p.x) + fx, static_cast<float>(p.y) + fy);
      chunk.film.push_back(f);
      chunk.rays.push_back(ctx.camera.generateRay(f.x, f.y));
    }
  }
}

// Each light's visibility from every hit of the chunk (chunk.shadows): one occlusion stream per
// light. `limit` false starts the rays on the traced triangles (trace-only frames).
void traceChunkShadows(const RenderContext& ctx, Chunk& chunk, bool limit) {
  const size_t n = chunk.rays.size();
  chunk.shadows.assign(n, LightShadows{});
  const size_t lights = std::min(ctx.lightsPerSample(), static_cast<size_t>(kMaxShadowedLights));
  std::vector<Vec3>& starts = chunk.starts;
  starts.resize(n);
  for (size_t s = 0; s < n; ++s) {
    const SampleHit& h = chunk.hits[s];
    if (!h.found) continue;
    const Ray& ray = chunk.rays[s];
    // Without `limit` (trace-only frames evaluate no limit surface) or on displaced
    // micropolygons, the rays start on the traced triangle.
    const bool displaced = ctx.objects[h.hit.mesh].displaced;
    starts[s] = shadowRayStart({.hit = ray.origin + h.hit.t * ray.direction,
                                .facetN = h.facet,
                                .V = -ray.direction,
                                .rayT = h.hit.t,
                                .limitP = limit && !displaced ? &h.limitP : nullptr});
  }
  for (size_t k = 0; k < lights; ++k) {
    chunk.shadowRays.clear();
    chunk.shadowOf.clear();
    for (size_t s = 0; s < n; ++s) {
      Ray ray;
      const Light& light = chunk.lightsOf(ctx, s)[k];
      if (chunk.hits[s].found && (light.colour != Vec3(0.0f) && light.intensity != 0.0f) &&
          shadowRay(light, starts[s], ray,
                    shadowSample(chunk.film[s], k, ctx.scene->render.seed))) {
        chunk.shadowRays.push_back(ray);
        chunk.shadowOf.push_back(static_cast<uint32_t>(s));
      }
    }
    chunk.occluded.resize(chunk.shadowRays.size());
    ctx.rays->occluded(chunk.shadowRays, chunk.occluded);
    for (size_t r = 0; r < chunk.shadowRays.size(); ++r)
      if (chunk.occluded[r]) chunk.shadows[chunk.shadowOf[r]].light[k] = {0.0f, 0.0f};
  }
}

// Traces the chunk's camera rays and evaluates the limit surface at each hit (trace-only frames
// only take the hits' facet normals).
void traceChunk(const RenderContext& ctx, const RenderOptions& options, Chunk& chunk) {
  const size_t n = chunk.rays.size();
  chunk.rayHits.resize(n);
  chunk.found.resize(n);
  chunk.hits.resize(n);
  ctx.rays->intersect(chunk.rays, chunk.rayHits, chunk.found);
  for (size_t s = 0; s < n; ++s) {
    SampleHit& h = chunk.hits[s];
    h.hit = chunk.rayHits[s];
    h.found = chunk.found[s] != 0;
    if (!h.found) continue;
    if (options.traceOnly)
      h.facet = facetNormal(h.hit, -chunk.rays[s].direction);
    else
      evaluateHit(ctx, chunk.rays[s], h);
  }
  sampleChunkLights(ctx, options.seed, options.traceOnly, chunk);
  const bool shadows =
      ctx.shadows && ctx.lightsPerSample() > 0 && (!options.traceOnly || options.traceShadowRays);
  if (shadows) traceChunkShadows(ctx, chunk, !options.traceOnly);
}

// Renders pixels (in order) of one tile: chunk by chunk, trace, then shade and write each pixel.
void renderPixels(const RenderContext& ctx, const RenderOptions& options,
                  std::span<const Pixel> pixels, Image& film, Chunk& chunk, int64_t& rays,
                  int64_t& nonFinite, ShareCounts& shares) {
  const int spp = options.spp;
  // Image pixel of the film's (0, 0).
  const Pixel origin = options.window ? Pixel(options.window->x0, options.window->y0) : Pixel(0, 0);
  const size_t perChunk = static_cast<size_t>(std::max(1, kChunkSamples / spp));
  // A pixel averages its samples, so each sample filters over 1/sqrt(spp) of the pixel.
  const float pixelScale =
      options.filterTextures ? 1.0f / std::sqrt(static_cast<float>(spp)) : 0.0f;
  const float footprintScale =
      options.filterBump ? 1.0f / std::sqrt(static_cast<float>(spp)) : 0.0f;
  const LightShadows lit;
  for (size_t first = 0; first < pixels.size(); first += perChunk) {
    const std::span<const Pixel> part =
        pixels.subspan(first, std::min(perChunk, pixels.size() - first));
    generateChunk(ctx, options, ctx.camera.settings().width, part, chunk);
    traceChunk(ctx, options, chunk);
    const bool shadowed = ctx.shadows && ctx.lightsPerSample() > 0 && !options.traceOnly;
    for (size_t p = 0; p < part.size(); ++p) {
      PixelSum sum;
      for (int i = 0; i < spp; ++i) {
        const size_t s = p * static_cast<size_t>(spp) + static_cast<size_t>(i);
        const SampleHit& h = chunk.hits[s];
        if (options.traceOnly) {  // no shading: no renderer to count either
          if (h.found) sum.depth += h.hit.t, sum.hits += 1;
          continue;
        }
        shadeSample(ctx, chunk.rays[s], chunk.film[s].x, chunk.film[s].y, footprintScale,
                    pixelScale, h, chunk.lightsOf(ctx, s), shadowed ? chunk.shadows[s] : lit, sum,
                    shares);
      }
      rays += spp;
      writePixel(sum, spp, options.falseColour, part[p].x - origin.x, part[p].y - origin.y, film,
                 nonFinite);
    }
  }
}

}  // namespace

Image renderFrame(const RenderContext& ctx, const RenderOptions& options,
                  RenderCounters& counters) {
  const CameraSettings& cam = ctx.camera.settings();
  const PixelWindow w = options.window.value_or(PixelWindow{0, 0, cam.width, cam.height});
  if (w.x0 < 0 || w.y0 < 0 || w.x1 > cam.width || w.y1 > cam.height || w.width() <= 0 ||
      w.height() <= 0)
    throw Error("render window [" + std::to_string(w.x0) + ", " + std::to_string(w.x1) + ") x [" +
                std::to_string(w.y0) + ", " + std::to_string(w.y1) + ") is not inside the " +
                std::to_string(cam.width) + "x" + std::to_string(cam.height) + " image");
  Image film = FilmLayout::make(w.width(), w.height());
  const int tilesX = (w.width() + kTileSize - 1) / kTileSize;
  const int tilesY = (w.height() + kTileSize - 1) / kTileSize;
  ProgressBar progress("render", static_cast<int64_t>(tilesX) * tilesY, options.progress);
  tbb::parallel_for(tbb::blocked_range2d<int>(0, tilesY, 1, 0, tilesX, 1),
                    [&](const tbb::blocked_range2d<int>& r) {
                      Chunk chunk;
                      std::vector<Pixel> pixels;
                      for (int ty = r.rows().begin(); ty < r.rows().end(); ++ty) {
                        for (int tx = r.cols().begin(); tx < r.cols().end(); ++tx) {
                          if (options.cancel && options.cancel->load(std::memory_order_relaxed))
                            return;
                          int64_t rays = 0, nonFinite = 0;
                          ShareCounts shares{};
                          pixels.clear();
                          for (int y = w.y0 + ty * kTileSize;
                               y < std::min(w.y0 + (ty + 1) * kTileSize, w.y1); ++y)
                            for (int x = w.x0 + tx * kTileSize;
                                 x < std::min(w.x0 + (tx + 1) * kTileSize, w.x1); ++x)
                              pixels.emplace_back(x, y);
                          renderPixels(ctx, options, pixels, film, chunk, rays, nonFinite, shares);
                          counters.rays.fetch_add(rays, std::memory_order_relaxed);
                          for (int k = 0; k < kSampleRenderers; ++k)
                            counters.shares[k].fetch_add(shares[k], std::memory_order_relaxed);
                          if (nonFinite)
                            counters.nonFinite.fetch_add(nonFinite, std::memory_order_relaxed);
                          progress.advance();
                        }
                      }
                    });
  progress.finish();
  if (options.cancel && options.cancel->load()) throw Interrupted();
  return film;
}

}  // namespace meso
