// `--set KEY=VALUE` (scene_options.h).
#include "scene_options.h"

#include "cli_options.h"

#include "meso/core/error.h"

namespace meso::app {

CLI::Option* addSetOption(CLI::App* command, std::vector<std::string>& set) {
  return addOption(command, "--set", set,
                   "KEY=VALUE: set a scene key as if the file said KEY = VALUE (camera.fov=30, "
                   "render.algorithm=bump, camera.resolution=[320,180], materials[1].kd=0.5); "
                   "repeatable, checked like the file")
      ->allow_extra_args(false)
      ->default_str("none");
}

std::vector<SceneOverride> setOverrides(const std::vector<std::string>& set) {
  std::vector<SceneOverride> out;
  for (const std::string& text : set) {
    const size_t eq = text.find('=');
    const size_t first = text.find_first_not_of(" \t"), last = text.find_last_not_of(" \t", eq - 1);
    if (eq == std::string::npos || first >= eq || last == std::string::npos || last < first)
      throw Error("--set: expected KEY=VALUE (render.D=3, camera.resolution=[320,180]), got \"" +
                  text + "\"");
    out.push_back({.origin = "--set",
                   .key = text.substr(first, last + 1 - first),
                   .value = text.substr(eq + 1)});
  }
  return out;
}

}  // namespace meso::app
