// The world length of one unit of (u, v) along the direction where it is longest, max(|P_u|,
// |P_v|), made continuous over a mesh's faces. The limit surface is smooth but its face-varying uv
// is linear inside each face, so P_u and P_v jump at every face edge; T, which reads that length,
// would then pick renderers face by face (a patchwork in the false-colour image of a mesh whose uv
// was unwrapped by a modelling tool). Here each control vertex takes the mean of the length at its
// corner of every face around it, and a point interpolates its face's corners: bilinear in st on a
// quad, linear on a triangle (an edge's points depend on its two corners only, so neighbouring
// faces agree), the corners' mean on other faces.
#pragma once

#include "meso/core/math.h"
#include "meso/geometry/control_mesh.h"
#include "meso/geometry/limit_surface.h"

#include <cstdint>
#include <vector>

namespace meso {

class UvSpeed {
 public:
  UvSpeed() = default;  // empty: at() gives 0
  // `surface` is the limit surface of `mesh` (one base face per control face).
  UvSpeed(const ControlMesh& mesh, const LimitSurface& surface);
  bool empty() const { return corner_.empty(); }
  // The length at patch coordinates st of base face `face`; 0 when empty or where no corner of the
  // face has a finite length.
  float at(int face, Vec2 st) const;
  // The largest of the face's corners: no point of the face exceeds it.
  float faceMax(int face) const;
  // The bytes its arrays hold.
  size_t memoryBytes() const;

 private:
  // How at() interpolates a face's corners: bilinearly over a quad whose corners lie at the unit
  // square's in patch coordinates, barycentrically over a triangle's corner coordinates, else
  // their mean.
  enum Kind : uint8_t { kMean, kUnitQuad, kTriangle };
  std::vector<int> first_;     // per face: its first corner in corner_ (faces + 1 entries)
  std::vector<float> corner_;  // per face corner: the mean over the faces around its vertex
  std::vector<uint8_t> kind_;  // per face
  // The patch coordinates of the triangles' corners, 3 from triangleSt_[3 triangle_[face]]: only
  // a mesh with triangles has these (a grid of quads keeps 21 bytes a face in all).
  std::vector<int> triangle_;
  std::vector<Vec2> triangleSt_;
};

}  // namespace meso
