// Everything a frame needs: limit surfaces and relief tables prepared once per scene, and the
// tessellation and Embree scene of the current camera, rebuilt per frame where they depend on it.
#pragma once

#include "meso/appearance/material_tables.h"
#include "meso/core/memory_budget.h"
#include "meso/core/texture_lookup.h"
#include "meso/core/warnings.h"
#include "meso/geometry/limit_surface.h"
#include "meso/geometry/uv_speed.h"
#include "meso/geometry/ray_scene.h"
#include "meso/geometry/tessellation.h"
#include "meso/render/displacement.h"
#include "meso/render/environment_map.h"
#include "meso/scene/camera.h"
#include "meso/scene/scene.h"

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace meso {

struct PreparedObject {
  LimitSurface surface;
  TessellatedMesh mesh;  // of the current frame
  // Its Embree grid blocks (displaced objects): they alone hold most of its micropolygons
  // (DicingSettings::gridsOnly, TessellatedMesh::gridOnlyTriangles).
  std::vector<TriangleGrid> grids;
  int material = 0;
  // Where its points lie in its material's solid relief (inactive for relief over (u, v)).
  SolidSpace solid;
  // Displaced micropolygons (view-dependent, rebuilt per frame) rather than the limit surface
  // drawn undisplaced.
  bool displaced = false;
  // Drawn undisplaced and tessellated per frame by view (render.tessellation_rate 0 and a curved
  // face): split until the limit surface is within DicingSettings::coarseTolerance pixels of the
  // chords, rate 1 out of view; otherwise the uniform tessellation, built once.
  bool byView = false;
  // affineFaces of its limit surface, for the uniform tessellation of an object drawn undisplaced
  // (released once it is made).
  std::vector<uint8_t> affine;
  // The length per unit of u that T reads, continuous across faces (relief over (u, v) on a mesh
  // with uv; empty otherwise).
  UvSpeed uvSpeed;
};

// Wall-clock seconds of the preparation phases, for --stats.
struct PrepareTimes {
  double load = 0.0;    // reading control meshes
  double tables = 0.0;  // building or loading appearance tables
  int tablesBuilt = 0;
  int tablesFromCache = 0;
  double tessellate = 0.0;  // limit surfaces and tessellation (all frames)
  double bvh = 0.0;         // Embree builds (all frames)
};

// What building one frame's geometry did.
struct FrameGeometryStats {
  double tessellateSeconds = 0.0;
  double bvhSeconds = 0.0;
  size_t triangles = 0;               // in the Embree scene
  size_t micropolygons = 0;           // of that, displaced micropolygons
  size_t offScreenMicropolygons = 0;  // of those, none of whose vertices is in view
  int facesDiced = 0;
  float coarsening = 1.0f;  // > 1 when the micropolygon cap coarsened dicing (the worst factor)
  // The nearest distance from the eye beyond which the cap coarsened some object's dicing
  // (AdaptiveTessellationStats::coarsenedBeyond; infinity: nowhere).
  float coarsenedBeyond = std::numeric_limits<float>::infinity();
  size_t embreePeakBytes = 0;
  size_t meshBytes = 0;  // what meso keeps of the displaced meshes (hit -> patch coordinates, and
                         // the points Embree reads in place)
  bool rebuilt = false;  // false: the previous frame's geometry was reused
};

// The per-frame state passed down to the renderers (no global mutable state).
struct RenderContext {
  const Scene* scene = nullptr;
  Camera camera;
  std::vector<PreparedObject> objects;  // index == RayScene mesh index
  std::unique_ptr<RayScene> rays;
  std::vector<MaterialRelief> reliefs;  // per material; empty levels for materials no object uses
  Warnings warnings;                    // e.g. a corrupt table cache file that was rebuilt
  Algorithm algorithm = Algorithm::Auto;
  bool facetNormals = false;  // render.normals = facet
  bool shadows = false;       // render.shadows: shadow rays and tabulated self-shadowing
  // Colour textures (kd, ks images): the lookups and, per material, the index of its kd and ks
  // texture in them (-1: the constant colour).
  std::shared_ptr<TextureLookup> textures;
  struct MaterialTextures {
    int kd = -1, ks = -1;
  };
  std::vector<MaterialTextures> materialTextures;
  bool textured(int material) const {
    return static_cast<size_t>(material) < materialTextures.size() &&
           (materialTextures[material].kd >= 0 || materialTextures[material].ks >= 0);
  }
  // The scene's environment, when it has one that emits (null otherwise): each camera sample adds
  // render.light_samples directional lights drawn from it to the scene's lights.
  std::shared_ptr<const EnvironmentMap> environment;
  // How many lights shade each camera sample: the scene's, then the environment's samples.
  size_t lightsPerSample() const {
    return scene->lights.size() +
           (environment ? static_cast<size_t>(scene->render.lightSamples) : size_t{0});
  }
  // The command's --memory-limit.
  uint64_t memoryLimitBytes = defaultMemoryLimitBytes();
  // What is held of it before a frame's geometry is made: the film and tables (as the command
  // estimated them), the objects' limit surfaces and the dicing's arrays per face. Undisplaced
  // geometry that would not fit beside it is refused before it is made; displaced micropolygons
  // are held to maxMicropolygons (the lower of render.max_micropolygons and what fits).
  double heldBytes = 0.0;
  size_t maxMicropolygons = std::numeric_limits<size_t>::max();
  // Every object's box (its limit surface's patch points), grown by its displacement bound where
  // it is displaced: where the frame's points lie (DicingSettings::ShadowCasters).
  Vec3 sceneLo{0.0f}, sceneHi{0.0f};
  // True: displaced objects keep every face out of view (as one-cell grids), not only those that
  // may shadow the view; for tests that compare the two.
  bool keepFacesOutOfView = false;
  // True: displaced objects keep their meshes' points and triangle indices after the frame's Embree
  // scene has copied them (tests that look at the displaced geometry). Shading needs only each
  // triangle's face and patch coordinates, so by default they are released before the BVH build.
  bool keepMeshPoints = false;

  size_t numTriangles() const { return rays ? rays->numTriangles() : 0; }
  // True when some object's geometry depends on the camera (displaced relief, or an object
  // tessellated by view).
  bool viewDependent() const;
};

// What prepareRenderContext does besides loading the scene and building its tables.
struct PrepareOptions {
  bool buildFrame = true;  // the geometry of the scene's own camera (prepareFrame)
  // The tables' histograms keep their masses (`meso tables` plots them;
  // TableSettings::keepHistograms).
  bool keepHistograms = false;
  bool progress = true;  // the tables' progress bar (drawn only when stderr is a terminal)
  // The command's --memory-limit: images (height, NDF, colour, environment) larger than it allows
  // are refused before they are decoded.
  uint64_t memoryLimitBytes = defaultMemoryLimitBytes();
  // What the command estimated for the film and tables (checkRenderMemory): taken off
  // memoryLimitBytes, with the limit surfaces, before micropolygons are diced.
  double reservedBytes = 0.0;
  // >= 0: what the command estimated for the film and its encodings (allocated after the frame's
  // geometry). The process's own memory is then measured once the tables and limit surfaces are
  // made (anonymousRssMib: they, and whatever reading the meshes left in malloc's heap), and held
  // with the film and the dicing's arrays where that exceeds the estimate above. Negative: the
  // estimate alone (meso trade, whose process holds earlier configurations' freed heap), as under
  // AddressSanitizer.
  double filmBytes = -1.0;
  bool dices = true;  // false: no frame is diced (meso tables), so dicing memory is not counted
};

// Loads every object's mesh, builds its limit surface and the relief tables of the materials that
// objects use (only those), then (unless options.buildFrame is false) the geometry of the scene's
// own camera (prepareFrame). The tables serve the views of the scene's camera and of every frame
// of its path (render.tables.frame_views, view_rows.h): a caller that renders other views of a
// flat surface sets that to false.
RenderContext prepareRenderContext(const Scene& scene, PrepareTimes& times,
                                   const PrepareOptions& options = {});

// Frees the frame's geometry (its Embree scene and the objects' meshes and grids) once nothing is
// rendered from it; the next prepareFrame makes it again.
void releaseFrameGeometry(RenderContext& ctx);

// Sets the camera and builds the frame's geometry: objects whose material has relief are diced
// into displaced micropolygons where the algorithm raises relief in this view (everywhere for
// displacement, where T can exceed e3 for auto); the others are drawn undisplaced, by view
// (PreparedObject::byView, under the same micropolygon cap) or with the uniform tessellation of
// render.tessellation_rate, built on the first call and reused after. Warnings (a micropolygon cap
// that coarsened dicing) are added to ctx.warnings.
FrameGeometryStats prepareFrame(RenderContext& ctx, const CameraSettings& camera,
                                PrepareTimes& times);

}  // namespace meso
