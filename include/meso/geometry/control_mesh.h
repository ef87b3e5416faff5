// The control cage of a subdivision surface: polygons with optional face-varying texture
// coordinates.
#pragma once

#include "meso/core/math.h"

#include <vector>

namespace meso {

enum class SubdivisionScheme { CatmullClark, Loop, Bilinear };

struct ControlMesh {
  std::vector<Vec3> positions;
  std::vector<int> faceSizes;     // vertices per face
  std::vector<int> faceVertices;  // concatenated vertex indices, faceSizes[f] per face
  // Optional face-varying (u, v): uvIndices parallels faceVertices and indexes uvs. Empty if
  // absent.
  std::vector<Vec2> uvs;
  std::vector<int> uvIndices;

  int numFaces() const { return static_cast<int>(faceSizes.size()); }
  bool hasUvs() const { return !uvIndices.empty(); }
};

// Applies an affine transform to the positions (uvs unchanged).
void transformControlMesh(ControlMesh& mesh, const Mat4& transform);

}  // namespace meso
