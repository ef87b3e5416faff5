// Everything a frame needs, prepared once: limit surfaces, tessellations, the Embree scene, the camera.
#pragma once

#include "meso/geometry/limit_surface.h"
#include "meso/geometry/ray_scene.h"
#include "meso/geometry/tessellation.h"
#include "meso/render/relief_levels.h"
#include "meso/scene/camera.h"
#include "meso/scene/scene.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace meso {

struct PreparedObject {
  LimitSurface surface;
  TessellatedMesh mesh;
  int material = 0;
};

// Wall-clock seconds of the preparation phases, for --stats.
struct PrepareTimes {
  double load = 0.0;        // reading control meshes
  double tables = 0.0;      // building or loading appearance tables
  int tablesBuilt = 0;
  int tablesFromCache = 0;
  double tessellate = 0.0;  // limit surfaces and tessellation
  double bvh = 0.0;         // Embree build
};

// render.algorithm, parsed once so the per-sample path compares no strings.
enum class Algorithm { Auto, Brdf, Bump, Redistribution, Displacement };
Algorithm parseAlgorithm(const std::string& name);

// The per-frame state passed down to the renderers (no global mutable state).
struct RenderContext {
  const Scene* scene = nullptr;
  Camera camera;
  std::vector<PreparedObject> objects;  // index == RayScene mesh index
  std::unique_ptr<RayScene> rays;
  std::vector<MaterialRelief> reliefs;  // per material; empty levels for materials no object uses
  std::vector<std::string> warnings;    // e.g. a corrupt table cache file that was rebuilt
  Algorithm algorithm = Algorithm::Auto;

  size_t numTriangles() const { return rays ? rays->numTriangles() : 0; }
};

// Loads every object's mesh, builds its limit surface, tessellates it and builds the Embree scene;
// builds the relief tables of the materials that objects use (only those).
RenderContext prepareRenderContext(const Scene& scene, PrepareTimes& times);

}  // namespace meso
