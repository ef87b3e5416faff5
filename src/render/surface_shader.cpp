// Becker & Max 1993, sections 2 to 4: per sample and per relief level, the renderer that T picks.
#include "meso/render/surface_shader.h"

#include "meso/render/level_shading.h"
#include "meso/render/relief_shadowing.h"
#include "meso/render/shading.h"
#include "meso/render/synthesis_shader.h"
#include "meso/render/transition.h"
#include "meso/relief/level_frames.h"
#include "meso/relief/schilling_phong.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace meso {

TileMap tableTileMap(const MaterialRelief& relief, const MetricPosition& metric, const Vec3& Pu,
                     const Vec3& Pv, const Vec3& N) {
  const MetricShape& s = relief.metrics[metric.k0].shape;
  const Vec3 pu = s.identity() ? Pu : Pu / s.a, pv = s.identity() ? Pv : s.a * Pv - s.b * Pu;
  return makeTileMap(pu, pv, N,
                     tableLengthPerU(areaLengthPerU(pu, pv), relief.metrics[metric.k0].lengthPerU,
                                     relief.metrics[metric.k1].lengthPerU));
}

namespace {

// The frame a level perturbs: level i+1 rides on level i's surface (section 2.3).
struct LevelFrame {
  Vec3 Pu, Pv, N;
};

struct LevelContext {
  const RenderContext& ctx;
  std::span<const Light> lights;  // the sample's: the scene's, then the environment's samples
  const Reflectance& material;    // the material's, or its colour textures' at the hit
  const MaterialRelief& relief;
  const SurfacePoint& sp;  // as reliefChart gives it, at the hit
  ReliefCoord coord;       // where the levels are evaluated (at the limit point)
  Vec3 V;
  float distance;
  bool raised;  // the object's geometry carries the displacement of levels whose T exceeds e3
  const Footprint* footprint;
  const LevelTransitions* transitions;    // T, weights and disp per level (auto mode only)
  MetricPosition metric;                  // where the surface's metric falls between table classes
  const LightShadows* shadows = nullptr;  // macro visibility per light; null: no shadows at all
};

// The frame's tangents as the class's shape sees them: [P_u, P_v] [[a, b], [0, 1/a]]^-1, so that a
// surface of exactly the class's metric has orthonormal tangents (times its length).
LevelFrame unshaped(const LevelFrame& f, const MetricShape& s) {
  if (s.identity()) return f;
  return {f.Pu / s.a, s.a * f.Pv - s.b * f.Pu, f.N};
}

// The tile map the level's BRDF and self-shadowing tables are looked up through on frame f, at
// the frame's own length clamped to the two classes' around the limit surface's metric
// (tableLengthPerU), as redistribution's maps carry a stretch beyond the classes.
TileMap brdfTileMap(const LevelContext& c, const LevelFrame& shaped) {
  return tableTileMap(c.relief, c.metric, shaped.Pu, shaped.Pv, shaped.N);
}

// The level after level i in a walk over tables: a band whose table is the sum of its image's
// finer bands stands for them (ReliefLevel::partialSum).
size_t nextTabulated(const LevelContext& c, size_t i) {
  const ReliefLevel& level = c.relief.levels[i];
  return level.partialSum ? std::max(level.partialSumEnd, i + 1) : i + 1;
}

// The self-shadowing tables of levels first .. last - 1 at the surface's metric (the finer bands of
// an image whose partial sum is tabulated have no table of their own to add).
ShadowingLevels shadowingLevels(const LevelContext& c, size_t first, size_t last) {
  ShadowingLevels s;
  s.w = c.metric.w;
  for (size_t k = first; k < last; k = nextTabulated(c, k))
    s.add(c.relief.tables(k, c.metric.k0).shadowing, c.relief.tables(k, c.metric.k1).shadowing);
  return s;
}

// Level i's self-shadowing factor per light on frame f (docs/shadows.md); lights that `macro`
// blocks are skipped.
LightShadows levelShadowing(const LevelContext& c, size_t i, const LevelFrame& f,
                            const LightShadows* macro) {
  return reliefShadowing(c.lights, c.sp.P, brdfTileMap(c, f), c.V, shadowingLevels(c, i, i + 1),
                         macro);
}

// The level's BRDF renderer on frame f, mixing the two metric classes around the surface's own.
// With shadows, each light is scaled by `shadows` times the self-shadowing of this level and of
// every finer one (the BRDF stands for all of them), looked up at this frame's angles; `own` (may
// be null) receives levelShadowing(c, i, shaped, shadows) from the same lookups.
Vec3 levelBrdf(const LevelContext& c, size_t i, const LevelFrame& shaped,
               const LightShadows* shadows, LightShadows* own = nullptr) {
  const TileMap m = brdfTileMap(c, shaped);
  const BrdfTable& t0 = c.relief.tables(i, c.metric.k0).brdf;
  const BrdfTable& t1 = c.relief.tables(i, c.metric.k1).brdf;
  return shadeBrdfShadowed(
      c.material, c.lights, c.sp.P, m, c.V, t0, t1, c.metric.w, shadows ? *shadows : LightShadows{},
      shadows ? shadowingLevels(c, i, c.relief.levels.size()) : ShadowingLevels{},
      shadows ? own : nullptr);
}

// The level's redistributed normal on frame f. Each class's map is exact in distribution; near the
// middle between two classes their normals are mixed so that the map stays continuous over a
// surface whose metric varies.
Vec3 levelRedistribution(const LevelContext& c, size_t i, const LevelFrame& f, float disp,
                         const Vec3& nBump) {
  const auto at = [&](int k) {
    const LevelFrame g = unshaped(f, c.relief.metrics[k].shape);
    const TileMap m = makeTileMap(g.Pu, g.Pv, g.N, c.relief.metrics[k].lengthPerU);
    return redistributeNormal(c.relief.tables(i, k).redistribution, m, c.V, disp, nBump);
  };
  const float t = std::clamp((c.metric.w - 0.4f) / 0.2f, 0.0f, 1.0f);
  if (c.metric.k0 == c.metric.k1 || t <= 0.0f) return at(c.metric.k0);
  if (t >= 1.0f) return at(c.metric.k1);
  const Vec3 n = glm::mix(at(c.metric.k0), at(c.metric.k1), t);
  const float len = glm::length(n);
  return len > 1e-6f && std::isfinite(len) ? n / len : at(c.metric.k0);
}

// The level's Blinn normal on frame f for its bump derivatives B, and the frame of the next level.
Vec3 bumpNormal(Vec2 B, LevelFrame& f) {
  const Vec3 n = blinnNormal(f.Pu, f.Pv, f.N, B.x, B.y);
  f.Pu += B.x * f.N;
  f.Pv += B.y * f.N;
  return n;
}

Vec3 bumpNormal(const ReliefLevel& level, const ReliefCoord& at, LevelFrame& f) {
  return bumpNormal(level.derivatives(at), f);
}

// Below the finest relief level: fractal NDF synthesis when the material declares an NDF, else the
// local model. `own` is the algorithm colour of the level above, mixed towards synthesis by how
// much synthesized detail shows.
ShadeResult shadeBottom(const LevelContext& c, const LevelFrame& f, const Vec3& own,
                        const LightShadows* shadows) {
  ShadeResult r;
  if (!c.relief.synthesis) {
    r.colour = shadeLocal(c.material, c.lights, c.sp.P, f.N, c.V, shadows);
    r.normal = f.N;
    r.algorithm = own;
    return r;
  }
  const float lengthPerU = std::min(glm::length(c.sp.Pu), glm::length(c.sp.Pv));
  const float cosV = std::max(glm::dot(f.N, c.V), 0.1f);
  const float pixelsPerUnit =
      c.distance > 0.0f ? c.ctx.camera.pixelsPerRadian() * lengthPerU * cosV / c.distance : 1e30f;
  const SynthesisShade s = shadeSynthesisLevel(*c.relief.synthesis, c.material, c.lights, c.sp.P,
                                               f.Pu, f.N, c.V, c.sp.uv, pixelsPerUnit, shadows);
  r.colour = s.colour;
  r.normal = s.normal;
  r.synthesis = s.weight;
  r.algorithm = glm::mix(own, algorithm_colour::kSynthesis, s.weight);
  return r;
}

// Shades levels i.. on frame f (auto mode), DESIGN.md section 3. Below e2 the paper blends the
// intensities of the BRDF and of redistribution (which hands over to the next level); above e3 the
// level's geometry was raised by disp = ramp(T; e3, e4) when the frame was tessellated, and its
// normal goes through theta_W (n' = R_thetaV(R_thetaW^-1(n)), exactly the Blinn normal at disp =
// 1); the next level then shades that surface with the renderer its own T picks. With shadows,
// `shadows` is the light that reaches level i (macro visibility times the coarser levels'
// self-shadowing); level i adds its own factor where it is not displaced (mixed towards 1 by disp:
// raised geometry casts real shadows).
// `raisedFrame`: f is exactly the raised geometric frame transitions->frames[i] (every coarser
// level was raised whole and the front side is shaded), so a level raised whole takes its next
// frame from there instead of evaluating its Blinn normal again.
ShadeResult shadeAuto(const LevelContext& c, size_t i, LevelFrame f, const LightShadows* shadows,
                      bool raisedFrame) {
  if (i >= c.relief.levels.size()) return shadeBottom(c, f, algorithm_colour::kSmooth, shadows);
  ShadeResult r;
  const ReliefLevel& level = c.relief.levels[i];
  const float T = c.transitions->T[i];
  const TransitionWeights& w = c.transitions->weights[i];
  const float disp = c.raised ? c.transitions->disp[i] : 0.0f;
  // A band of an image not raised whole is drawn with its image's finer bands as one level (its
  // tables are of their sum); raised whole, the next band shades its surface.
  const bool sum = level.partialSum && disp < 1.0f;
  const size_t after = sum ? level.partialSumEnd : i + 1;
  const bool finest = after >= c.relief.levels.size();
  r.disp[i] = disp;
  // This level's self-shadowing, when both the BRDF and the finer levels need it.
  LightShadows own;
  const bool shareOwn = shadows && w.brdf > 0.0f && w.brdf < 1.0f && disp < 1.0f;
  if (w.brdf > 0.0f) {
    r.colour = w.brdf * levelBrdf(c, i, f, shadows, shareOwn ? &own : nullptr);
    r.algorithm = w.brdf * algorithm_colour::kBrdf;
  }
  r.T = T;
  r.normal = f.N;
  if (w.brdf < 1.0f) {
    LevelFrame next = f;
    raisedFrame = raisedFrame && disp >= 1.0f;
    if (raisedFrame) {
      // nextFrame(frames[i], B_i): the same tangents and Blinn normal as bumpNormal's.
      const SurfaceFrame& g = c.transitions->frames[i + 1];
      next = {g.Pu, g.Pv, g.N};
    } else {
      // Raised levels' derivatives were evaluated with T (levelTransitions), at the same uv.
      const Vec3 nBump = sum ? bumpNormal(*level.partialSum, c.coord, next)
                         : static_cast<int>(i) < c.transitions->raised
                             ? bumpNormal(c.transitions->B[i], next)
                             : bumpNormal(level, c.coord, next);
      next.N = disp >= 1.0f ? nBump : levelRedistribution(c, i, f, disp, nBump);
    }
    LightShadows below;
    if (shadows && disp >= 1.0f) {
      below = *shadows;  // a level raised whole casts real shadows: its factor mixes to 1
    } else if (shadows) {
      below = shareOwn ? own : levelShadowing(c, i, f, shadows);
      for (LightShadow& s : below.light)
        s = {s.diffuse + disp * (1.0f - s.diffuse), s.specular + disp * (1.0f - s.specular)};
      below *= *shadows;
    }
    const ShadeResult finer = shadeAuto(c, after, next, shadows ? &below : nullptr, raisedFrame);
    r.colour += (1.0f - w.brdf) * finer.colour;
    const Vec3 own =
        glm::mix(algorithm_colour::kRedistribution, algorithm_colour::kDisplacement, disp);
    r.algorithm +=
        (1.0f - w.brdf) *
        (finest ? glm::mix(own, algorithm_colour::kSynthesis, finer.synthesis) : finer.algorithm);
    r.synthesis = (1.0f - w.brdf) * finer.synthesis;
    r.normal = finer.normal;
    for (size_t k = after; k < c.relief.levels.size() && k < kMaxReliefLevels; ++k)
      r.disp[k] = finer.disp[k];
    if (!finest && w.brdf == 0.0f) r.T = finer.T;
  }
  return r;
}

// Schilling's antialiased bump mapping: each level's slope is the pyramid's mean over the
// footprint, and the slope covariance that averaging removed widens the highlight (Appendix A).
ShadeResult shadeFilteredBump(const LevelContext& c, LevelFrame f) {
  const size_t n = std::min(c.relief.levels.size(), static_cast<size_t>(kMaxReliefLevels));
  std::array<SlopeCovariance, kMaxReliefLevels> K{};
  std::array<LevelFrame, kMaxReliefLevels> frames{};
  const Footprint& fp = *c.footprint;
  for (size_t i = 0; i < n; ++i) {
    const ReliefLevel& level = c.relief.levels[i];
    frames[i] = f;
    Vec2 B = level.derivatives(c.coord);
    if (level.pyramid) {
      const Vec2 size(static_cast<float>(level.pyramid->width()),
                      static_cast<float>(level.pyramid->height()));
      const SlopeSample s = level.pyramid
                                ->lookup(level.scale * c.sp.uv, level.scale * fp.dUVdx * size,
                                         level.scale * fp.dUVdy * size)
                                .scaled(level.amplitude * level.scale);
      B = s.mean;
      K[i] = s.roughness;
    }
    const Vec3 nBump = blinnNormal(f.Pu, f.Pv, f.N, B.x, B.y);
    f.Pu += B.x * f.N;
    f.Pv += B.y * f.N;
    f.N = nBump;
  }
  Vec3 e1 = f.Pu - glm::dot(f.Pu, f.N) * f.N;
  const float len = glm::length(e1);
  e1 =
      len > 1e-12f && std::isfinite(len)
          ? e1 / len
          : glm::normalize(glm::cross(f.N, std::abs(f.N.x) < 0.9f ? Vec3(1, 0, 0) : Vec3(0, 1, 0)));
  const Vec3 e2 = glm::cross(f.N, e1);
  // Below the finest level: synthesized detail continues the relief (its own lobe replaces the
  // roughness that filtering removed); without it, Schilling's widened highlight.
  if (c.relief.synthesis) return shadeBottom(c, f, algorithm_colour::kBump, c.shadows);
  SlopeCovariance roughness;
  for (size_t i = 0; i < n; ++i)
    roughness += tangentCovariance(K[i], frames[i].Pu, frames[i].Pv, e1, e2);
  ShadeResult r;
  r.colour = shadeRoughened(c.material, c.lights, c.sp.P, f.N, c.V, e1, e2, roughness, c.shadows);
  r.algorithm = algorithm_colour::kBump;
  r.normal = f.N;
  return r;
}

ShadeResult shadeFixed(const LevelContext& c, Algorithm algorithm, LevelFrame f) {
  if (algorithm == Algorithm::Bump && c.footprint && c.footprint->valid)
    return shadeFilteredBump(c, f);
  ShadeResult r;
  if (algorithm == Algorithm::Brdf) {
    r.colour = levelBrdf(c, 0, f, c.shadows);
    r.algorithm = algorithm_colour::kBrdf;
    r.normal = f.N;
    return r;
  }
  // Redistribution carries each level's self-shadowing factor; displacement traced real shadow
  // rays; bump (the inconsistent baseline) has macro shadows only.
  LightShadows shadows = c.shadows ? *c.shadows : LightShadows{};
  const bool redistribution = algorithm == Algorithm::Redistribution;
  for (size_t i = 0; i < c.relief.levels.size(); i = redistribution ? nextTabulated(c, i) : i + 1) {
    const LevelFrame before = f;
    // Redistribution draws an image's bands from a partial sum on as one level (its tables).
    const ReliefLevel& level = c.relief.levels[i];
    const Vec3 nBump =
        bumpNormal(redistribution && level.partialSum ? *level.partialSum : level, c.coord, f);
    if (algorithm == Algorithm::Redistribution && c.shadows)
      shadows *= levelShadowing(c, i, before, &shadows);
    f.N = algorithm == Algorithm::Redistribution ? levelRedistribution(c, i, before, 0.0f, nBump)
                                                 : nBump;
  }
  return shadeBottom(c, f,
                     algorithm == Algorithm::Redistribution ? algorithm_colour::kRedistribution
                     : algorithm == Algorithm::Displacement ? algorithm_colour::kDisplacement
                                                            : algorithm_colour::kBump,
                     c.shadows ? &shadows : nullptr);
}

// The local model at normal N: no relief, or --normals facet.
ShadeResult shadeLocalAt(std::span<const Light> lights, const Reflectance& material, const Vec3& P,
                         const Vec3& N, const Vec3& V, const LightShadows* shadows,
                         const Vec3& algorithm) {
  ShadeResult r;
  r.normal = N;
  r.colour = shadeLocal(material, lights, P, r.normal, V, shadows);
  r.algorithm = algorithm;
  return r;
}

LevelContext levelContext(const RenderContext& ctx, std::span<const Light> lights,
                          const PreparedObject& object, const Reflectance& material,
                          const SurfacePoint& sp, const ReliefCoord& coord, const Vec3& V,
                          const Footprint* footprint, const LevelTransitions* transitions,
                          MetricPosition metric, const LightShadows* shadows) {
  return {ctx,
          lights,
          material,
          ctx.reliefs[object.material],
          sp,
          coord,
          V,
          glm::length(sp.P - ctx.camera.position()),
          object.displaced,
          footprint,
          transitions,
          metric,
          shadows};
}

}  // namespace

ShadeResult shadeSurface(const RenderContext& ctx, const PreparedObject& object,
                         const SurfacePoint& hit, const Vec3& V, std::span<const Light> lights,
                         const Vec3* facetNormal, const Footprint* footprint, const Vec3* limitP,
                         const LightShadows* shadows, const Reflectance* reflectance,
                         float lengthPerU) {
  // T, weights, disp and the levels' heights come from the limit point (hit.P is the limit surface
  // at the hit's patch coordinates, moved to the raised hit when displaced), exactly as the
  // tessellator raised the geometry; shading happens at the hit.
  ReliefCoord coord;
  SurfacePoint limit =
      reliefChart({limitP ? *limitP : hit.P, hit.Pu, hit.Pv, hit.N, hit.uv}, object.solid, coord);
  SurfacePoint sp = limit;
  sp.P = hit.P;
  const Reflectance& material = reflectance ? *reflectance : ctx.scene->materials[object.material];
  const MaterialRelief& relief = ctx.reliefs[object.material];
  // Shade the side that faces the eye (open meshes such as a ground plane are seen from either
  // side).
  const bool back = glm::dot(sp.N, V) < 0.0f;
  LevelFrame frame{sp.Pu, sp.Pv, back ? -sp.N : sp.N};
  if (relief.levels.empty() && !relief.synthesis)
    return shadeLocalAt(lights, material, sp.P, frame.N, V, shadows, algorithm_colour::kSmooth);
  if (facetNormal && ctx.algorithm == Algorithm::Displacement && object.displaced)
    // --normals facet: the micropolygon's own normal, for comparison with the Blinn normal.
    return shadeLocalAt(lights, material, sp.P,
                        glm::dot(*facetNormal, V) < 0.0f ? -*facetNormal : *facetNormal, V, shadows,
                        algorithm_colour::kDisplacement);
  if (relief.levels.empty())  // an NDF alone
    return shadeBottom(
        levelContext(ctx, lights, object, material, sp, coord, V, footprint, nullptr, {}, shadows),
        frame, algorithm_colour::kSmooth, shadows);
  const LevelTransitions transitions =
      ctx.algorithm == Algorithm::Auto
          ? levelTransitions(
                relief, limit, coord, ctx.camera.position(), ctx.camera.pixelsPerRadian(),
                ctx.scene->render.transition, DisplacementMode::ByTransition,
                ctx.shadows ? std::span<const Light>(ctx.scene->lights) : std::span<const Light>(),
                TransitionsFor::Shading, object.solid.active ? 0.0f : lengthPerU)
          : LevelTransitions{};
  const LevelContext c = levelContext(ctx, lights, object, material, sp, coord, V, footprint,
                                      &transitions, relief.metricAt(sp.Pu, sp.Pv), shadows);
  return ctx.algorithm == Algorithm::Auto ? shadeAuto(c, 0, frame, shadows, !back)
                                          : shadeFixed(c, ctx.algorithm, frame);
}

}  // namespace meso
