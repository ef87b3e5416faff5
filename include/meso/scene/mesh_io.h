// Reads OBJ, PLY and OFF control meshes with OpenMesh.
#pragma once

#include "meso/geometry/control_mesh.h"

#include <filesystem>
#include <string_view>

namespace meso {

// Throws meso::Error ("FILE: message") for missing, unreadable, malformed or faceless meshes.
// The file must be a regular file of at most kMaxMeshBytes (core/input_file.h).
ControlMesh loadControlMesh(const std::filesystem::path& file);

// The same from bytes already in memory; `file` names them in messages and its extension picks the
// format (for the mesh fuzzer and for loadControlMesh).
ControlMesh parseControlMesh(std::string_view bytes, const std::filesystem::path& file);

}  // namespace meso
