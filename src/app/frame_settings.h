// The settings a path's frames are rendered with, kept beside them in `.NAME.meso-settings`, so
// that a run resuming the path with other settings is refused instead of mixing frames of two
// renders.
#pragma once

#include "render_options.h"

#include "meso/scene/scene.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>

namespace meso::app {

// out/f.exr -> out/.f.meso-settings.
std::filesystem::path settingsFileFor(const std::filesystem::path& output);

// What changes a frame's pixels: the scene file's text (FNV-1a of its bytes, `sceneText`), every
// --set, the scene's settings after the options (render_stats.h settingsJson, without the
// threads and the file names) and the flags and crop window the renderer takes. Files the scene
// names (meshes, images) count by name only.
nlohmann::json frameSettings(const Scene& scene, const std::string& sceneText,
                             const RenderCommandOptions& o,
                             const std::optional<PixelWindow>& window);

// Throws meso::Error when frames of `output`'s path (NAME_0000.exr or .png ...) are on disk and
// its settings file holds other settings than `settings`, naming those that differ and --overwrite.
// Frames without a settings file (or a file that is not JSON) are taken as they are.
void checkResumedSettings(const std::filesystem::path& output, const nlohmann::json& settings);

// Writes `settings` to the settings file atomically, unless it already holds them.
void storeFrameSettings(const std::filesystem::path& output, const nlohmann::json& settings);

}  // namespace meso::app
