// Reads a TOML scene (docs/scene-format.md). Every problem is a meso::Error naming
// FILE:LINE:COL: key: what was expected.
#pragma once

#include "meso/core/memory_budget.h"
#include "meso/scene/scene.h"

#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace meso {

// A scene key set from the command line, as if the file said `key = value`.
struct SceneOverride {
  std::string origin;  // the option that set it (--set, --fov): errors about it name it
  std::string key;     // dotted: camera.fov, render.D, materials[1].kd
  std::string value;   // TOML (a bare word such as bump is taken as a string)
};

// Reads and validates the scene file. Relative paths inside are resolved against its folder and
// must name readable files. `overrides` are set in order before the file is read, so each is
// checked exactly as the file's keys are and errors about it read "ORIGIN: key: what was expected".
// Height images are read to plan their bands (expandImageBands), each refused before decoding when
// larger than memoryLimitBytes allows.
Scene loadScene(const std::filesystem::path& file, std::span<const SceneOverride> overrides = {},
                uint64_t memoryLimitBytes = defaultMemoryLimitBytes());

// The same from text; `file` names the source in messages and anchors relative paths.
Scene parseScene(std::string_view text, const std::filesystem::path& file,
                 std::span<const SceneOverride> overrides = {});

}  // namespace meso
