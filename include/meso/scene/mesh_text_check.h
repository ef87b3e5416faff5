// Checks the text of OBJ and ASCII OFF meshes before OpenMesh reads them. OpenMesh skips what it
// cannot use (a face with an index out of range, a NaN vertex) and trusts what it reads (an OFF
// face of -5 vertices made it allocate 4 GB), so a broken file used to end in "mesh has no faces",
// or in a silently different mesh. Every problem is reported as FILE:LINE:COL: key: what was
// expected.
#pragma once

#include <filesystem>
#include <string_view>

namespace meso {

struct MeshTextCounts {
  long long vertices = 0, faces = 0, texcoords = 0;
  bool checked = false;  // false: a format (binary OFF, PLY) left to OpenMesh and checked after it
};

// `ext` is ".obj", ".off" or ".ply" (lower case). Throws meso::Error for the first problem found.
MeshTextCounts checkMeshText(std::string_view bytes, const std::filesystem::path& file,
                             const std::string& ext);

}  // namespace meso
