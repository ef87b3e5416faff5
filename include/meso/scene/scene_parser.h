// Reads a TOML scene (docs/scene-format.md). Every problem is a meso::Error naming
// FILE:LINE:COL: key: what was expected.
#pragma once

#include "meso/scene/scene.h"

#include <filesystem>
#include <string_view>

namespace meso {

// Reads and validates the scene file. Relative paths inside are resolved against its folder and
// must name readable files.
Scene loadScene(const std::filesystem::path& file);

// The same from text; `file` names the source in messages and anchors relative paths.
Scene parseScene(std::string_view text, const std::filesystem::path& file);

}  // namespace meso
