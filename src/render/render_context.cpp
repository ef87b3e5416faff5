#include "meso/render/render_context.h"

#include "meso/core/huge_pages.h"
#include "meso/core/progress.h"
#include "meso/core/timer.h"
#include "meso/geometry/adaptive_tessellation.h"
#include "meso/geometry/flat_faces.h"
#include "meso/render/displacement.h"
#include "meso/render/tile_map.h"
#include "meso/render/view_rows.h"
#include "meso/scene/mesh_io.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <optional>
#include <string>

namespace meso {

namespace {

bool raisesRelief(Algorithm a) { return a == Algorithm::Auto || a == Algorithm::Displacement; }

// The metrics (length per unit of u and shape) of a surface, sampled at every face's corners, edge
// midpoints and centre: the metric classes its tables need. Returns whether the normals there
// differ (a curved surface, whose crests bound the visible height of flat levels:
// buildVisibleHeights).
bool sampleMetrics(const LimitSurface& surface, std::vector<MetricClass>& out) {
  // Faces in parallel, each into its own slots: the samples in face order whatever the threads.
  const int faces = surface.numFaces();
  std::vector<size_t> offset(static_cast<size_t>(faces) + 1, 0);
  for (int face = 0; face < faces; ++face)
    offset[face + 1] = offset[face] + 2 * static_cast<size_t>(surface.faceSize(face)) + 1;
  const size_t first = out.size();
  out.resize(first + offset.back());
  std::vector<uint8_t> differs(static_cast<size_t>(faces), 0);
  std::optional<Vec3> N0;  // the normal at the first sample, which every other is compared with
  if (faces > 0) N0 = surface.evaluate(0, surface.cornerSt(0, 0)).N;
  tbb::parallel_for(tbb::blocked_range<int>(0, faces), [&](const tbb::blocked_range<int>& range) {
    // A face with the derivatives of one evaluated before has its samples (DerivativeSweep).
    DerivativeSweep sweep(surface);
    for (int face = range.begin(); face != range.end(); ++face) {
      size_t at = first + offset[face];
      if (const int same = sweep.sameAs(face); same >= 0) {
        std::copy_n(out.begin() + static_cast<std::ptrdiff_t>(first + offset[same]),
                    offset[face + 1] - offset[face], out.begin() + static_cast<std::ptrdiff_t>(at));
        differs[face] = differs[same];
        continue;
      }
      const auto sample = [&](const SurfacePoint& sp) {
        out[at++] = metricOf(sp.Pu, sp.Pv);
        differs[face] |= !(glm::dot(*N0, sp.N) > 1.0f - 1e-6f);
      };
      const int n = surface.faceSize(face);
      Vec2 centre(0.0f);
      for (int k = 0; k < n; ++k) {
        const Vec2 a = surface.cornerSt(face, k), b = surface.cornerSt(face, (k + 1) % n);
        centre += a / static_cast<float>(n);
        for (const Vec2 st : {a, 0.5f * (a + b)}) sample(surface.evaluate(face, st));
      }
      sample(surface.evaluate(face, centre));
    }
  });
  return std::any_of(differs.begin(), differs.end(), [](uint8_t d) { return d != 0; });
}

// A warning when the mesh lies so far from the origin that float positions are spaced more than
// 0.1% of its size apart there (its shape, relief and metric are lost: a torus 2 units wide at
// x = 1e7, where floats are 1 unit apart, once asked for 332 table sets).
std::optional<std::string> precisionWarning(const ControlMesh& mesh, const std::string& name) {
  if (mesh.positions.empty()) return std::nullopt;
  Vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  for (const Vec3& p : mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const Vec3 extent = hi - lo;
  const float size = std::max({extent.x, extent.y, extent.z});
  const float far = std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z), std::abs(hi.x),
                              std::abs(hi.y), std::abs(hi.z)});
  const float spacing = far * std::numeric_limits<float>::epsilon();
  if (!std::isfinite(far) || !(spacing > 1e-3f * size)) return std::nullopt;
  return fmt::format(
      "{}: it lies {:g} units from the origin, where positions (32-bit floats) are {:g} apart, "
      "{:.3g}% of its size ({:g}): its shape and relief are not kept there; move the scene "
      "nearer the origin",
      name, far, spacing, 100.0f * spacing / size, size);
}

}  // namespace

namespace {

// The kd and ks images of the materials that objects use, prepared for the TextureSystem.
void loadColourTextures(RenderContext& ctx, const std::filesystem::path& folder,
                        uint64_t memoryLimitBytes) {
  const Scene& scene = *ctx.scene;
  ctx.materialTextures.assign(scene.materials.size(), {});
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    const bool used = std::any_of(ctx.objects.begin(), ctx.objects.end(),
                                  [&](const auto& o) { return o.material == static_cast<int>(m); });
    const Material& material = scene.materials[m];
    const auto add = [&](const ColourTexture& t, const char* key) {
      if (t.file.empty() || !used) return -1;
      if (!ctx.textures) ctx.textures = std::make_shared<TextureLookup>();
      try {
        return ctx.textures->add(t.file, t.space, folder, memoryLimitBytes);
      } catch (const Error& e) {
        throw Error(t.loc, std::string("materials.") + key, e.what());
      }
    };
    ctx.materialTextures[m] = {add(material.kdTexture, "kd"), add(material.ksTexture, "ks")};
  }
}

// What dicing holds per control face of an object tessellated per frame (none for the others).
double dicingBytesPerFace(const PreparedObject& o) {
  if (o.displaced) return kDicingBytesPerFace;
  return o.byView ? kViewTessellationBytesPerFace : 0.0;
}

// A frame gives the memory its tessellation freed back to the system before the BVH build
// (docs/performance.md) when it made this many displaced micropolygons (a second or more of
// tessellation and BVH build on 2 cores; the release costs a flight of small frames about 10 ms
// a frame), or freed this much by the estimate of dicing's temporaries and the meshes' indices
// (objects tessellated by view with nothing displaced).
constexpr size_t kReleaseMicropolygons = 4'000'000;
constexpr double kReleasedBytes = 128.0 * 1024 * 1024;

}  // namespace

bool RenderContext::viewDependent() const {
  for (const PreparedObject& o : objects)
    if (o.displaced || o.byView) return true;
  return false;
}

namespace {

// What --memory-limit leaves for the frames' geometry once the film and tables (estimated by the
// command: options.reservedBytes), the objects' limit surfaces and, for objects tessellated per
// frame, the dicing's own arrays per face are held (ctx.heldBytes): undisplaced tessellation beyond
// it is refused, and the micropolygon cap is lowered to fit in it.
void fitGeometryInMemory(RenderContext& ctx, const PrepareOptions& options) {
  double surfaces = 0.0, dicing = 0.0, largest = 0.0;
  size_t largestObject = 0;
  int64_t faces = 0;
  for (size_t k = 0; k < ctx.objects.size(); ++k) {
    const PreparedObject& o = ctx.objects[k];
    const double bytes = double(o.surface.memoryBytes()) + double(o.uvSpeed.memoryBytes());
    surfaces += bytes;
    if (options.dices) dicing += dicingBytesPerFace(o) * o.surface.numFaces();
    faces += o.surface.numFaces();
    if (bytes > largest) largest = bytes, largestObject = k;
  }
  ctx.heldBytes = options.reservedBytes + surfaces + dicing;
  std::string what = "the limit surfaces of " + std::to_string(faces) + " control faces " +
                     formatMib(surfaces) +
                     (dicing > 0.0 ? ", their dicing " + formatMib(dicing) : "") +
                     ", the film and tables " + formatMib(options.reservedBytes);
  // The process as measured: a large mesh's reading leaves its transient arrays in malloc's heap
  // (reused by later blocks, never returned), which the estimate above does not see. Not under
  // AddressSanitizer, whose shadow memory and quarantine are most of what it would measure.
  if (options.filmBytes >= 0.0 && kHugeNewBuilt) {
    const double process = anonymousRssMib() * 1024.0 * 1024.0;
    const double measured = process + options.filmBytes + dicing;
    if (measured > ctx.heldBytes) {
      ctx.heldBytes = measured;
      what = "the process so far " + formatMib(process) + " (its tables, the limit surfaces of " +
             std::to_string(faces) + " control faces and what reading them left in the heap)" +
             (dicing > 0.0 ? ", their dicing " + formatMib(dicing) : "") + ", the film " +
             formatMib(options.filmBytes);
    }
  }
  const double limit = static_cast<double>(options.memoryLimitBytes);
  if (!ctx.objects.empty())
    requireMemoryWithin(options.memoryLimitBytes, ctx.heldBytes,
                        ctx.scene->objects[largestObject].mesh.string(), "mesh", what);
  const RenderSettings& rs = ctx.scene->render;
  const int64_t fits = std::max<int64_t>(
      static_cast<int64_t>(std::max(0.0, limit - ctx.heldBytes) / kBytesPerMicropolygon), 1000);
  if (fits >= rs.maxMicropolygons) return;
  ctx.maxMicropolygons = static_cast<size_t>(fits);
  if (dicing > 0.0)
    ctx.warnings.add("render.max_micropolygons: lowered from " +
                     std::to_string(rs.maxMicropolygons) + " to " + std::to_string(fits) +
                     " so that the micropolygons fit in the memory limit of " + formatMib(limit) +
                     " (--memory-limit) beside " + what);
}

void setSceneBox(RenderContext& ctx) {
  Vec3 lo(std::numeric_limits<float>::infinity()), hi(-lo);
  for (const PreparedObject& o : ctx.objects) {
    const float grow =
        o.displaced ? std::max(displacementBound(ctx.reliefs[o.material]), 0.0f) : 0.0f;
    Vec3 flo, fhi;
    for (int f = 0; f < o.surface.numFaces(); ++f)
      if (o.surface.faceBox(f, flo, fhi)) {
        lo = glm::min(lo, flo - Vec3(grow));
        hi = glm::max(hi, fhi + Vec3(grow));
      }
  }
  ctx.sceneLo = lo;
  ctx.sceneHi = hi;
}

}  // namespace

RenderContext prepareRenderContext(const Scene& scene, PrepareTimes& times,
                                   const PrepareOptions& options) {
  RenderContext ctx{&scene,
                    Camera(scene.camera),
                    {},
                    nullptr,
                    {},
                    {},
                    scene.render.algorithm,
                    scene.render.normals == ShadingNormals::Facet,
                    scene.render.shadows,
                    {},
                    {},
                    nullptr};
  ctx.memoryLimitBytes = options.memoryLimitBytes;
  if (scene.environment) {
    auto env = std::make_shared<EnvironmentMap>(
        EnvironmentMap::load(*scene.environment, options.memoryLimitBytes));
    if (!env->black()) ctx.environment = std::move(env);
  }
  ctx.reliefs.resize(scene.materials.size());
  for (const Object& object : scene.objects) {
    Timer load;
    ControlMesh mesh = loadControlMesh(object.mesh);
    transformControlMesh(mesh, object.transform);
    if (std::optional<std::string> w = precisionWarning(mesh, object.mesh.string()))
      ctx.warnings.add(*w);
    times.load += load.seconds();
    Timer tess;
    const Material& material = scene.materials[object.material];
    std::string scaleWarning;
    const SolidSpace solid = solidSpace(material, object.transform, &scaleWarning);
    if (!scaleWarning.empty()) ctx.warnings.add(object.mesh.string() + ": " + scaleWarning);
    if (!mesh.hasUvs() && hasRelief(material) && !solid.active)
      ctx.warnings.add(object.mesh.string() +
                       ": the mesh has no texture coordinates (vt): its relief follows each "
                       "face's own (s, t) chart and does not continue across faces");
    LimitSurface surface = [&] {
      try {
        return LimitSurface(mesh, object.scheme);
      } catch (const Error& e) {
        throw Error(object.mesh.string() + ": " + e.what());
      }
    }();
    UvSpeed speed =
        hasRelief(material) && !solid.active && mesh.hasUvs() ? UvSpeed(mesh, surface) : UvSpeed();
    times.tessellate += tess.seconds();
    ctx.objects.push_back(PreparedObject{.surface = std::move(surface),
                                         .mesh = {},
                                         .grids = {},
                                         .material = object.material,
                                         .solid = solid,
                                         .displaced = false,
                                         .byView = false,
                                         .affine = {},
                                         .uvSpeed = std::move(speed)});
  }
  Timer tables;
  const std::filesystem::path cacheFolder =
      scene.render.cacheDir.empty() ? TableCache::defaultFolder() : scene.render.cacheDir;
  const TableCache cache(cacheFolder);
  loadColourTextures(ctx, cacheFolder / "textures", options.memoryLimitBytes);
  TableSettings settings = tableSettings(scene.render.tables);
  // Self-shadowing tables only where a far-field renderer draws relief: bump ignores relief
  // shadows, displacement traces them.
  settings.shadows = scene.render.shadows && ctx.algorithm != Algorithm::Bump &&
                     ctx.algorithm != Algorithm::Displacement;
  settings.build = ctx.algorithm != Algorithm::Bump && ctx.algorithm != Algorithm::Displacement;
  settings.keepHistograms = options.keepHistograms;
  settings.memoryLimitBytes = options.memoryLimitBytes;
  // The metric classes of every material first, so that one progress line counts every table set
  // of the scene (with its ETA) instead of one line per material.
  struct Plan {
    size_t material;
    std::vector<MetricClass> classes;
    bool curved;
  };
  std::vector<Plan> plans;
  int64_t sets = 0;
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    std::vector<MetricClass> samples;
    bool used = false, curved = false;
    for (const PreparedObject& o : ctx.objects)
      if (o.material == static_cast<int>(m)) {
        // Solid relief sees every surface through a unit-speed isotropic chart (reliefChart):
        // one class per length of a unit of solid space, whatever the parameterization.
        std::vector<MetricClass> uvMetrics;
        curved = sampleMetrics(o.surface, o.solid.active ? uvMetrics : samples) || curved;
        if (o.solid.active) samples.push_back({o.solid.lengthPerUnit, MetricShape{}});
        used = true;
      }
    if (!used || !hasRelief(scene.materials[m])) continue;
    float step = scene.render.tables.metricStep;
    std::vector<MetricClass> classes = metricClassesFor(samples, step, &step);
    if (step > scene.render.tables.metricStep) {
      ctx.warnings.warn(
          "material '{}': its surfaces' metrics (uv stretch, shear and length per unit of u) "
          "need more than {} table sets per level at render.tables.metric_step {:g}; they were "
          "binned at a step of {:g} octaves into {} (is a mesh far from the origin, or its uv "
          "degenerate?)",
          scene.materials[m].name, kMaxMetricClasses, scene.render.tables.metricStep, step,
          classes.size());
    }
    if (settings.build)
      sets += static_cast<int64_t>(std::max<size_t>(classes.size(), 1) *
                                   scene.materials[m].relief.size());
    plans.push_back({m, std::move(classes), curved});
  }
  // The BRDF and self-shadowing tables only on the theta_V rows that the scene's frames can look
  // them up at (view_rows.h).
  std::vector<ScreenMetric> screens;
  for (const CameraSettings& c : sceneCameras(scene)) screens.push_back(Camera(c).screen());
  const auto levelRows = [&](size_t m) {
    return [&, m](const MaterialRelief& r) -> std::vector<ViewRows> {
      if (!scene.render.tables.frameViews) return {};
      std::vector<const LimitSurface*> surfaces;
      for (const PreparedObject& o : ctx.objects) {
        if (o.material != static_cast<int>(m)) continue;
        if (o.solid.active) return {};  // seen through its own chart, not the limit surface's
        surfaces.push_back(&o.surface);
      }
      return levelViewRows(surfaces, r, screens, displacementBound(r),
                           settings.histogram.resolution.thetaV, kThetaVMax);
    };
  };
  // Shown only when building takes longer than a second (tables read from the cache do not).
  ProgressBar progress("tables (" + std::to_string(sets) + " sets)", sets, options.progress,
                       std::chrono::milliseconds(1000));
  // Materials at once (the same tables whatever the thread count); warnings in material order.
  std::vector<Warnings> planWarnings(plans.size());
  tbb::parallel_for(size_t(0), plans.size(), [&](size_t p) {
    const size_t m = plans[p].material;
    ctx.reliefs[m] = buildMaterialRelief(scene.materials[m], cache, &planWarnings[p], settings,
                                         std::move(plans[p].classes), &progress, levelRows(m));
    if (ctx.algorithm == Algorithm::Bump) buildSlopePyramids(ctx.reliefs[m]);
    if (ctx.algorithm == Algorithm::Auto) buildVisibleHeights(ctx.reliefs[m], plans[p].curved);
  });
  for (size_t p = 0; p < plans.size(); ++p) {
    const MaterialRelief& r = ctx.reliefs[plans[p].material];
    ctx.warnings.append(std::move(planWarnings[p]));
    times.tablesBuilt += r.tablesBuilt;
    times.tablesFromCache += r.tablesFromCache;
  }
  progress.finish();
  times.tables += tables.seconds();
  Timer flat;
  for (PreparedObject& o : ctx.objects) {
    o.displaced = raisesRelief(ctx.algorithm) && !ctx.reliefs[o.material].levels.empty();
    if (o.displaced) continue;
    // Drawn undisplaced: by view where a face is curved (an object of flat faces is drawn exactly
    // by two triangles a face, once).
    o.affine = affineFaces(o.surface);
    if (scene.render.tessellationRate == 0)
      for (int f = 0; f < o.surface.numFaces() && !o.byView; ++f)
        o.byView = o.surface.hasLimitSurface(f) && !o.affine[static_cast<size_t>(f)];
    if (o.byView) std::vector<uint8_t>().swap(o.affine);
  }
  times.tessellate += flat.seconds();
  fitGeometryInMemory(ctx, options);
  setSceneBox(ctx);
  if (options.buildFrame) prepareFrame(ctx, scene.camera, times);
  return ctx;
}

namespace {

// What every displaced object of one frame shares: the view and the dicing settings (the
// micropolygon cap is the frame's, shared by its objects).
struct FrameDicing {
  const CameraSettings& view;
  ScreenMetric screen;
  DisplacementMode mode;
  DicingSettings dicing;
};

// What the frame's shadow rays may reach (DicingSettings::ShadowCasters): unset (every face kept)
// when some light's rays cannot be bounded so (an environment, a point light with a radius), or
// when a test asks for every face.
std::optional<DicingSettings::ShadowCasters> shadowCasters(const RenderContext& ctx) {
  if (ctx.keepFacesOutOfView || ctx.environment) return std::nullopt;
  if (!glm::all(glm::lessThanEqual(ctx.sceneLo, ctx.sceneHi))) return std::nullopt;
  DicingSettings::ShadowCasters c{
      .sceneLo = ctx.sceneLo, .sceneHi = ctx.sceneHi, .directions = {}, .points = {}};
  if (!ctx.shadows) return c;  // no shadow rays: nothing out of view is needed
  for (const Light& light : ctx.scene->lights) {
    if (light.type == LightType::Directional)
      c.directions.push_back(-light.direction);
    else if (light.type == LightType::Point && light.radius == 0.0f)
      c.points.push_back(light.position);
    else
      return std::nullopt;
  }
  return c;
}

FrameDicing frameDicing(const RenderContext& ctx, const CameraSettings& settings) {
  const RenderSettings& rs = ctx.scene->render;
  FrameDicing d{settings,
                ctx.camera.screen(),
                ctx.algorithm == Algorithm::Displacement ? DisplacementMode::Full
                                                         : DisplacementMode::ByTransition,
                {}};
  d.dicing.dicingRate = rs.dicingRate;
  d.dicing.metric = rs.dicingMetric;
  d.dicing.maxEdgeRate = 4096;
  d.dicing.maxMicropolygons =
      std::min(static_cast<size_t>(rs.maxMicropolygons), ctx.maxMicropolygons);
  d.dicing.gridsOnly = true;  // hits in grids know their face and st (40 bytes a micropolygon)
  // The displacement reference and renderer keep the whole cap in every direction.
  if (d.mode == DisplacementMode::ByTransition) d.dicing.acrossViewCap = rs.acrossViewCap;
  d.dicing.shadowCasters = shadowCasters(ctx);
  return d;
}

size_t meshBytes(const TessellatedMesh& m) {
  return m.positions.capacity() * sizeof(Vec3) + m.indices.capacity() * sizeof(uint32_t) +
         m.triangleFace.capacity() * sizeof(int) + m.cornerSt.capacity() * sizeof(Vec2);
}

// Tessellates the objects made per frame: dices and displaces the displaced ones, and tessellates
// those drawn undisplaced by view (nothing diced: the limit surface to the coarse tolerance), under
// one micropolygon cap (its farthest geometry coarsened first, whichever object it belongs to);
// their figures go to `stats` (micropolygons: the displaced objects').
void tessellateForFrame(RenderContext& ctx, const std::vector<size_t>& objects,
                        const FrameDicing& d, FrameGeometryStats& stats) {
  const RenderSettings& rs = ctx.scene->render;
  std::deque<ReliefDisplacement> displacements;  // not moved: the surfaces point to them
  std::vector<AdaptiveSurface> surfaces;
  for (size_t k : objects) {
    PreparedObject& object = ctx.objects[k];
    object.mesh = {};
    if (!object.displaced) {
      FaceDicing undiced;
      undiced.needsDicing.assign(static_cast<size_t>(object.surface.numFaces()), 0);
      surfaces.push_back({.surface = &object.surface, .faces = std::move(undiced)});
      continue;
    }
    const MaterialRelief& relief = ctx.reliefs[object.material];
    displacements.emplace_back(
        relief, d.mode, rs.transition, d.view.position, ctx.camera.pixelsPerRadian(),
        ctx.shadows ? std::span<const Light>(ctx.scene->lights) : std::span<const Light>(),
        &object.surface, object.solid, &object.uvSpeed);
    surfaces.push_back(
        {.surface = &object.surface,
         .faces = faceDicing(object.surface, relief, d.mode, rs.transition, d.view.position,
                             ctx.camera.pixelsPerRadian(), {rs.reliefSamples, rs.texelSamples},
                             object.solid, &object.uvSpeed, &d.screen),
         .displacement = &displacements.back()});
  }
  std::vector<AdaptiveTessellation> meshes = tessellateAdaptive(surfaces, d.screen, d.dicing);
  for (size_t i = 0; i < objects.size(); ++i) {
    AdaptiveTessellation& t = meshes[i];
    PreparedObject& object = ctx.objects[objects[i]];
    if (!t.warning.empty())
      ctx.warnings.add(ctx.scene->objects[objects[i]].mesh.string() + ": " + t.warning);
    if (object.displaced) {
      stats.micropolygons += t.stats.micropolygons;
      stats.offScreenMicropolygons += t.stats.offScreenMicropolygons;
      stats.facesDiced += t.stats.facesDiced;
    }
    stats.coarsening = std::max(stats.coarsening, t.stats.coarsening);
    stats.coarsenedBeyond = std::min(stats.coarsenedBeyond, t.stats.coarsenedBeyond);
    object.mesh = std::move(t.mesh);
    object.grids = std::move(t.grids);
  }
}

}  // namespace

void releaseFrameGeometry(RenderContext& ctx) {
  ctx.rays.reset();
  for (PreparedObject& o : ctx.objects) {
    o.mesh = TessellatedMesh();
    std::vector<TriangleGrid>().swap(o.grids);
  }
}

FrameGeometryStats prepareFrame(RenderContext& ctx, const CameraSettings& settings,
                                PrepareTimes& times) {
  ctx.camera = Camera(settings);
  FrameGeometryStats stats;
  if (ctx.rays && !ctx.viewDependent()) {
    stats.triangles = ctx.rays->numTriangles();
    return stats;
  }
  const FrameDicing d = frameDicing(ctx, settings);
  Timer tess;
  ctx.rays.reset();  // the previous frame's scene goes before this one's is built (peak memory)
  auto rays = std::make_unique<RayScene>();
  std::vector<size_t> perFrame;
  for (size_t k = 0; k < ctx.objects.size(); ++k) {
    PreparedObject& object = ctx.objects[k];
    if (object.displaced || object.byView) {
      perFrame.push_back(k);
    } else if (object.mesh.numTriangles() == 0) {
      object.mesh =
          tessellateSmooth(object.surface, std::max(ctx.scene->render.tessellationRate, 1),
                           ctx.memoryLimitBytes, ctx.scene->objects[k].mesh.string(), ctx.heldBytes,
                           object.affine.empty() ? nullptr : &object.affine);
      std::vector<uint8_t>().swap(object.affine);
    }
  }
  if (!perFrame.empty()) tessellateForFrame(ctx, perFrame, d, stats);
  stats.tessellateSeconds = tess.seconds();

  Timer bvh;
  // A frame's own meshes give the scene their points (Embree reads a grid mesh's in place, and
  // copies a triangle mesh's), and their indices go before the BVH build (the peak of a frame whose
  // mesh is not large: docs/performance.md): a hit needs only its triangle's face and patch
  // coordinates. Meshes kept from frame to frame are copied.
  for (PreparedObject& object : ctx.objects) {
    if ((object.displaced || object.byView) && !ctx.keepMeshPoints)
      rays->takeMesh(object.mesh, object.grids);
    else
      rays->addMesh(object.mesh, object.grids);
  }
  double freed = 0.0;  // dicing's temporaries and the indices released here
  for (PreparedObject& object : ctx.objects)
    if (object.displaced || object.byView) {
      freed += dicingBytesPerFace(object) * object.surface.numFaces();
      if (!ctx.keepMeshPoints) {
        freed += double(object.mesh.indices.capacity() * sizeof(uint32_t));
        std::vector<uint32_t>().swap(object.mesh.indices);
      }
      stats.meshBytes += meshBytes(object.mesh);
    }
  stats.meshBytes += rays->heldBytes();
  // What was freed stays in malloc's arenas (dicing's temporaries in those of the threads that
  // made them), and the BVH build, the frame's peak, would come on top of it. Less is reused by
  // the frame's later steps, which would fault its pages again (docs/performance.md).
  if (stats.micropolygons >= kReleaseMicropolygons || freed > kReleasedBytes) releaseFreedHeap();
  rays->commit();
  stats.bvhSeconds = bvh.seconds();
  stats.triangles = rays->numTriangles();
  stats.embreePeakBytes = rays->peakDeviceBytes();
  stats.rebuilt = true;
  ctx.rays = std::move(rays);
  times.tessellate += stats.tessellateSeconds;
  times.bvh += stats.bvhSeconds;
  return stats;
}

}  // namespace meso
