// Scene keys from the command line: `--set KEY=VALUE` on every command that reads a scene (render,
// consistency SCENE, tables, trade), applied by the scene reader (SceneOverride, scene_parser.h).
#pragma once

#include "meso/scene/scene_parser.h"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace meso::app {

// Adds the repeatable `--set KEY=VALUE` to `command`, collecting the texts in `set`.
CLI::Option* addSetOption(CLI::App* command, std::vector<std::string>& set);

// Each `--set` text as an override (origin "--set"), in order. Throws meso::Error naming --set
// when a text has no `=` or nothing before it.
std::vector<SceneOverride> setOverrides(const std::vector<std::string>& set);

}  // namespace meso::app
