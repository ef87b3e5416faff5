// Reads OBJ, PLY and OFF control meshes with OpenMesh.
#pragma once

#include "meso/geometry/control_mesh.h"

#include <filesystem>

namespace meso {

// Throws meso::Error ("FILE: message") for missing, unreadable, malformed or faceless meshes.
ControlMesh loadControlMesh(const std::filesystem::path& file);

}  // namespace meso
