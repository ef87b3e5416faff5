// Only the table entries a scene can use (docs/tables.md, "Only the views a scene needs"): the
// theta_V rows at which a material's BRDF and self-shadowing tables can be looked up by any frame
// of the scene.
#pragma once

#include "meso/appearance/material_tables.h"
#include "meso/geometry/limit_surface.h"
#include "meso/geometry/screen_metric.h"
#include "meso/scene/scene.h"

#include <limits>
#include <span>
#include <vector>

namespace meso {

// The cameras of every frame of the scene: its path's frames, or its one camera.
std::vector<CameraSettings> sceneCameras(const Scene& scene);

// A range of theta_V in the tables' tile space; `all` when it cannot be bounded.
struct ViewAngles {
  float lo = 0.0f;
  float hi = 0.5f * kPi;
  bool all = true;
  // The least and most the tile maps of the faces a screen sees scale tangent directions (1 and 1:
  // the tile's angles are the world's).
  float sMin = std::numeric_limits<float>::infinity();
  float sMax = 0.0f;
};

// The theta_V (in tile space, through tableTileMap at each face's metric position) at which the
// coarsest level of `relief` is looked up on the surfaces, seen from the screens: the level's
// frame is the limit surface's own there. Bounded only where every face that a screen may see
// (its box, grown by `bound`, the relief's displacement bound, in the view) is flat
// (faceIsAffine; faces no screen sees are not tested): over the part of each face inside each
// screen's view, with the eye moved by +-bound along the face's normal for the raised relief. A
// curved face in view can face the eye at any angle: all. `relief.metrics` must hold the
// classes' lengths and shapes.
ViewAngles coarsestViewAngles(std::span<const LimitSurface* const> surfaces,
                              const MaterialRelief& relief, std::span<const ScreenMetric> screens,
                              float bound);

// The rows of every level's BRDF and self-shadowing tables, coarsest first: the coarsest level's
// from coarsestViewAngles; a finer level's widened by the coarser levels' steepest tilts (its
// frame is tilted by them, and eq. (1) looks it up from the coarser level's normals) where the
// material has one isotropic class at the surfaces' own length, else every row.
std::vector<ViewRows> levelViewRows(std::span<const LimitSurface* const> surfaces,
                                    const MaterialRelief& relief,
                                    std::span<const ScreenMetric> screens, float bound, int n,
                                    float thetaVMax);

// The rows of a histogram layout (n theta_V slices over [0, thetaVMax]) that lookups at `angles`
// interpolate between.
ViewRows viewRowsFor(const ViewAngles& angles, int n, float thetaVMax);

}  // namespace meso
