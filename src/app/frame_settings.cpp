// A path's settings file (frame_settings.h).
#include "frame_settings.h"

#include "render_stats.h"

#include "meso/core/atomic_file.h"
#include "meso/core/error.h"
#include "meso/core/hash.h"

#include <fmt/format.h>

#include <cctype>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace meso::app {
namespace {

// NAME_0000.exr or NAME_0000.png (any number of digits) of the path written to `output`.
bool isFrameOf(const std::string& file, const std::string& stem) {
  if (file.size() < stem.size() + 6 || file.compare(0, stem.size() + 1, stem + "_") != 0)
    return false;
  const std::string tail = file.substr(file.size() - 4);
  if (tail != ".exr" && tail != ".png") return false;
  const std::string digits = file.substr(stem.size() + 1, file.size() - stem.size() - 5);
  for (char c : digits)
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  return !digits.empty();
}

bool framesOnDisk(const std::filesystem::path& output) {
  std::error_code ec;
  const std::filesystem::path folder =
      output.parent_path().empty() ? std::filesystem::path(".") : output.parent_path();
  for (const auto& e : std::filesystem::directory_iterator(folder, ec))
    if (isFrameOf(e.path().filename().string(), output.stem().string())) return true;
  return false;
}

std::optional<nlohmann::json> storedSettings(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) return std::nullopt;
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json stored = nlohmann::json::parse(text.str(), nullptr, false);
  if (stored.is_discarded() || !stored.is_object()) return std::nullopt;
  return stored;
}

// A setting's value in a message: numbers as printf's %g writes them (floats stored as doubles
// would show 0.30000001192092896).
std::string shown(const nlohmann::json& v) {
  if (v.is_number_float()) return fmt::format("{:g}", v.get<double>());
  if (!v.is_array()) return v.dump();
  std::string out = "[";
  for (const nlohmann::json& e : v) out.append(out.size() > 1 ? "," : "").append(shown(e));
  return out + "]";
}

// "spp 4 (now 8)", "transition.D 2 (now 3)", "the scene file's text": each setting that differs.
void differences(const nlohmann::json& before, const nlohmann::json& now, const std::string& name,
                 std::string& out) {
  if (before == now) return;
  if (before.is_object() && now.is_object()) {
    for (auto it = now.begin(); it != now.end(); ++it)
      differences(before.contains(it.key()) ? before[it.key()] : nlohmann::json(nullptr),
                  it.value(), name + it.key() + ".", out);
    for (auto it = before.begin(); it != before.end(); ++it)
      if (!now.contains(it.key()))
        differences(it.value(), nlohmann::json(nullptr), name + it.key() + ".", out);
    return;
  }
  const std::string key = name.substr(0, name.size() - 1);
  out.append(out.empty() ? "" : ", ")
      .append(key == "scene_text_fnv1a" ? std::string("the scene file's text")
                                        : key + " " + shown(before) + " (now " + shown(now) + ")");
}

}  // namespace

std::filesystem::path settingsFileFor(const std::filesystem::path& output) {
  return output.parent_path() / ("." + output.stem().string() + ".meso-settings");
}

nlohmann::json frameSettings(const Scene& scene, const std::string& sceneText,
                             const RenderCommandOptions& o,
                             const std::optional<PixelWindow>& window) {
  nlohmann::json s = settingsJson(scene, {});
  for (const char* where : {"scene", "output", "threads", "objects"}) s.erase(where);
  s["scene_text_fnv1a"] = fmt::format("{:016x}", Hasher().string(sceneText).digest());
  s["set"] = o.set;
  s["false_colour"] = o.falseColour;
  s["bump_filter"] = !o.noBumpFilter;
  s["texture_filter"] = !o.noTextureFilter;
  s["crop"] = window ? nlohmann::json{window->x0, window->y0, window->x1, window->y1}
                     : nlohmann::json(nullptr);
  return s;
}

void checkResumedSettings(const std::filesystem::path& output, const nlohmann::json& settings) {
  const std::filesystem::path file = settingsFileFor(output);
  const std::optional<nlohmann::json> stored = storedSettings(file);
  if (!stored || *stored == settings || !framesOnDisk(output)) return;
  std::string changed;
  differences(*stored, settings, "", changed);
  throw Error(file.string() + ": the frames of " + output.string() +
              " on disk were rendered with other settings (" + changed +
              "): pass --overwrite to render every frame again, or -o to write them elsewhere");
}

void storeFrameSettings(const std::filesystem::path& output, const nlohmann::json& settings) {
  const std::filesystem::path file = settingsFileFor(output);
  if (storedSettings(file) == settings) return;
  writeFileAtomically(file, settings.dump(2) + "\n");
}

}  // namespace meso::app
