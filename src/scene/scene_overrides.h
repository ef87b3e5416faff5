// Scene keys set from the command line (SceneOverride, scene_parser.h), applied to the file's TOML
// table before the reader sees it. Private to src/scene.
#pragma once

#include "meso/scene/scene_parser.h"

#include <toml++/toml.h>

#include <span>

namespace meso {

// Sets each override's key in `top` in order, creating missing tables; a [i] in the key indexes
// an array of tables ([[materials]]). Every node it adds has the override's origin as its source
// path, so the reader's errors about it name the option (TableReader::loc). Throws meso::Error
// naming the origin and the key when the key is malformed, runs through a value that is not a
// table, indexes past an array's end, or the value is not TOML.
void applySceneOverrides(toml::table& top, std::span<const SceneOverride> overrides);

}  // namespace meso
