#include "meso/render/integrator.h"

#include "meso/core/progress.h"
#include "meso/core/rng.h"
#include "meso/render/film_layout.h"
#include "meso/render/shadow_rays.h"
#include "meso/render/surface_shader.h"
#include "meso/render/transition.h"

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace meso {
namespace {

constexpr int kTileSize = 16;

// The paper's Figure 4 look: the algorithm colours, shaded by the beauty's brightness so the shapes
// stay readable.
Vec3 falseColour(const Vec3& beauty, const Vec3& algorithm) {
  const float lum = std::min(1.0f, 0.2126f * beauty.r + 0.7152f * beauty.g + 0.0722f * beauty.b);
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

// Shades one primary ray: position, frame and normal come from the limit surface at the hit's patch
// coordinates, never from the triangle (Chan 2002).
// footprintScale 0: no footprint (unfiltered bump lookups).
void traceSample(const RenderContext& ctx, const Ray& ray, float fx, float fy, float footprintScale,
                 PixelSum& sum, ShareCounts& shares) {
  RayHit hit;
  if (!ctx.rays->intersect(ray, hit)) {
    sum.colour += ctx.scene->render.background;
    addShare(shares, SampleRenderer::Background, 1.0f);
    return;
  }
  const PreparedObject& object = ctx.objects[hit.mesh];
  // A grid hit knows its face and patch coordinates; other triangles read the mesh's arrays.
  const bool fromGrid = hit.face >= 0;
  const int face = fromGrid ? hit.face : object.mesh.triangleFace[hit.triangle];
  SurfacePoint sp = object.surface.evaluate(
      face, fromGrid ? hit.st : object.mesh.patchCoords(hit.triangle, hit.b1, hit.b2));
  const Vec3 facet = facetNormal(hit, sp.N);
  const Vec3 limitP = sp.P;
  if (object.displaced)
    sp.P =
        ray.origin + hit.t * ray.direction;  // lights see the raised point, not the limit surface
  Footprint footprint;
  if (ctx.algorithm == Algorithm::Bump && footprintScale > 0.0f)  // only the bump renderer filters
    footprint = footprintAt(sp, ctx.camera.generateRay(fx + 1.0f, fy),
                            ctx.camera.generateRay(fx, fy + 1.0f), footprintScale);
  // Macro shadows: occlusion rays from the hit on the very triangles this frame traced.
  LightShadows shadows;
  if (ctx.shadows && !ctx.scene->lights.empty()) {
    ShadowOrigin o;
    o.hit = ray.origin + hit.t * ray.direction;
    o.facetN = facet;
    o.V = -ray.direction;
    o.rayT = hit.t;
    o.limitP = object.displaced ? nullptr : &limitP;
    shadows = traceShadows(*ctx.rays, ctx.scene->lights, o);
  }
  const ShadeResult r = shadeSurface(ctx, object, sp, -ray.direction,
                                     ctx.facetNormals && object.displaced ? &facet : nullptr,
                                     &footprint, &limitP, ctx.shadows ? &shadows : nullptr);
  sum.colour += r.colour;
  sum.algorithm += r.algorithm;
  sum.normal += r.normal;
  sum.T += r.T;
  sum.depth += hit.t;
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

void renderPixel(const RenderContext& ctx, const RenderOptions& options, int x, int y, Image& film,
                 int64_t& rays, int64_t& nonFinite, ShareCounts& shares) {
  const int spp = options.spp;
  const int cols = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(spp))));
  const int rows = (spp + cols - 1) / cols;
  const uint64_t pixelIndex = static_cast<uint64_t>(y) * film.width + x;
  Rng rng(options.seed, pixelIndex);
  PixelSum sum;
  // A pixel averages its samples, so each sample filters over 1/sqrt(spp) of the pixel.
  const float footprintScale =
      options.filterBump ? 1.0f / std::sqrt(static_cast<float>(spp)) : 0.0f;
  for (int i = 0; i < spp; ++i) {
    // Jittered stratum (i % cols, i / cols) of a cols x rows grid over the pixel.
    const float fx = (static_cast<float>(i % cols) + rng.uniform()) / static_cast<float>(cols);
    const float fy = (static_cast<float>(i / cols) + rng.uniform()) / static_cast<float>(rows);
    const float filmX = static_cast<float>(x) + fx, filmY = static_cast<float>(y) + fy;
    if (options.traceOnly) {  // no shading: no renderer to count either
      RayHit hit;
      const Ray ray = ctx.camera.generateRay(filmX, filmY);
      if (ctx.rays->intersect(ray, hit)) {
        sum.depth += hit.t;
        sum.hits += 1;
        if (options.traceShadowRays && ctx.shadows && !ctx.scene->lights.empty()) {
          ShadowOrigin o;
          o.hit = ray.origin + hit.t * ray.direction;
          o.facetN = facetNormal(hit, -ray.direction);
          o.V = -ray.direction;
          o.rayT = hit.t;
          traceShadows(*ctx.rays, ctx.scene->lights, o);  // Embree's calls: never elided
        }
      }
      continue;
    }
    traceSample(ctx, ctx.camera.generateRay(filmX, filmY), filmX, filmY, footprintScale, sum,
                shares);
  }
  rays += spp;
  writePixel(sum, spp, options.falseColour, x, y, film, nonFinite);
}

}  // namespace

Image renderFrame(const RenderContext& ctx, const RenderOptions& options,
                  RenderCounters& counters) {
  const CameraSettings& cam = ctx.camera.settings();
  Image film = FilmLayout::make(cam.width, cam.height);
  const int tilesX = (cam.width + kTileSize - 1) / kTileSize;
  const int tilesY = (cam.height + kTileSize - 1) / kTileSize;
  ProgressBar progress("render", static_cast<int64_t>(tilesX) * tilesY, options.progress);
  tbb::parallel_for(
      tbb::blocked_range2d<int>(0, tilesY, 1, 0, tilesX, 1),
      [&](const tbb::blocked_range2d<int>& r) {
        for (int ty = r.rows().begin(); ty < r.rows().end(); ++ty) {
          for (int tx = r.cols().begin(); tx < r.cols().end(); ++tx) {
            if (options.cancel && options.cancel->load(std::memory_order_relaxed)) return;
            int64_t rays = 0, nonFinite = 0;
            ShareCounts shares{};
            for (int y = ty * kTileSize; y < std::min((ty + 1) * kTileSize, cam.height); ++y)
              for (int x = tx * kTileSize; x < std::min((tx + 1) * kTileSize, cam.width); ++x)
                renderPixel(ctx, options, x, y, film, rays, nonFinite, shares);
            counters.rays.fetch_add(rays, std::memory_order_relaxed);
            for (int k = 0; k < kSampleRenderers; ++k)
              counters.shares[k].fetch_add(shares[k], std::memory_order_relaxed);
            if (nonFinite) counters.nonFinite.fetch_add(nonFinite, std::memory_order_relaxed);
            progress.advance();
          }
        }
      });
  progress.finish();
  if (options.cancel && options.cancel->load()) throw Interrupted();
  return film;
}

}  // namespace meso
