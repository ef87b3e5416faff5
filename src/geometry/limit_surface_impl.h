// Private to src/geometry: what LimitSurface prepares per base face, shared with the tessellator.
#pragma once

#include "meso/geometry/limit_surface.h"

#include <opensubdiv/bfr/parameterization.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/topologyRefiner.h>

#include <memory>
#include <vector>

namespace meso {

// meso's patch coordinates st equal Bfr's (u, v) for quads (unit square) and Loop triangles (the
// unit right triangle). Bfr parameterizes every other face (triangles and N-gons under
// Catmull-Clark or bilinear) by N quad sub-faces laid out as disjoint tiles, so a triangle of Bfr's
// tessellation can have corners in different tiles and interpolating their coordinates would be
// meaningless. For those faces meso's st lives in a continuous chart instead: the unit right
// triangle for N = 3, a regular N-gon inscribed in the unit square otherwise. Sub-face i is the
// kite (V_i, M_i, C, M_i-1) of the chart, mapped piecewise affinely (two triangles split along
// V_i-C) onto the sub-face's normalized square, so the map is continuous and orientation
// preserving.
struct LimitSurface::Impl {
  struct Face {
    OpenSubdiv::Bfr::Parameterization param;
    // Positions; invalid where the face has no limit surface.
    OpenSubdiv::Bfr::Surface<float> surface;
    // Face-varying (u, v); invalid without uvs.
    OpenSubdiv::Bfr::Surface<float> uvSurface;
    size_t patchOffset = 0;  // first float of this face's patch points
    size_t uvPatchOffset = 0;
    int chartOffset = -1;  // first chart point (N vertices, then the centre); -1: st is Bfr's
    Vec3 centroid{0.0f};
    Vec3 averageNormal{0.0f, 0.0f, 1.0f};  // fallback where the limit normal is undefined
  };

  std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> refiner;
  std::vector<Face> faces;
  std::vector<float> patchPoints;    // 3 floats per point
  std::vector<float> uvPatchPoints;  // 2 floats per point
  std::vector<Vec2> chartPoints;

  // Bfr coordinates of meso's st (clamped into the face) and their Jacobian d(Bfr uv)/d(st).
  Vec2 chartToBfr(int face, Vec2 st, glm::mat2& jacobian) const;
  // meso's st of a point given in Bfr coordinates.
  Vec2 bfrToChart(int face, Vec2 bfrUv) const;
};

}  // namespace meso
