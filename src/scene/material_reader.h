// The materials of a scene file (docs/scene-format.md): [[materials]] with their relief levels,
// NDF and colour images; and the check every file name of a scene passes. Internal to the scene
// reader.
#pragma once

#include "meso/scene/scene.h"

#include "table_reader.h"

#include <filesystem>
#include <string>

namespace meso {

// The file named by `key`, resolved against `base` (the scene's folder) unless absolute; fails at
// the key unless it names a readable regular file.
std::filesystem::path readablePath(TableReader& r, const std::string& key,
                                   const std::filesystem::path& base);

// One [[materials]] table.
Material readMaterial(TableReader& r, const std::filesystem::path& base);

}  // namespace meso
