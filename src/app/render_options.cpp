// `meso render`'s options (render_options.h).
#include "render_options.h"

#include "cli_options.h"
#include "cli_values.h"
#include "scene_options.h"

#include "meso/core/error.h"
#include "meso/render/transition.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace meso::app {

CLI::App* addRenderOptions(CLI::App& cli, RenderCommandOptions& o) {
  CLI::App* render =
      cli.add_subcommand("render", "Render a scene to OpenEXR (with layers) and a PNG preview");
  render->footer(
      "=VALUE after an option is its default; a scene key (camera.spp) there means the scene's "
      "value, whose own default docs/scene-format.md gives. Flags are off unless given.");
  addOption(render, "scene", o.scene, "Scene file (TOML, see docs/scene-format.md)")->required();
  addOption(render, "-o,--output", o.output,
            "Output .exr; the PNG preview is written beside it with the same name")
      ->default_str("out/<scene name>.exr");
  addOption(render, "--stats", o.statsFile,
            "Write timings, memory, counters and settings as JSON to this file")
      ->default_str("none");
  addSetOption(render, o.set);
  addOption(render, "--camera-position", o.cameraPosition,
            "X,Y,Z: the eye (camera.position; not with a [path])")
      ->default_str("camera.position");
  addOption(render, "--look-at", o.lookAt,
            "X,Y,Z: the point looked at (camera.look_at; not with a [path])")
      ->default_str("camera.look_at");
  addOption(render, "--fov", o.fov,
            "Vertical field of view in degrees (camera.fov; not with a [path])")
      ->default_str("camera.fov");
  addOption(render, "--spp", o.spp, "Samples per pixel (jittered strata)", CLI::Range(1, 65536))
      ->default_str("camera.spp");
  addOption(render, "--threads", o.threads, "Worker threads, 0 = all cores", CLI::Range(0, 1024))
      ->default_str("render.threads");
  addOption(render, "--seed", o.seed, "Random seed")->default_str("render.seed");
  addChoice(render, "--algorithm", o.algorithm, choiceList<Algorithm>("|"))
      ->default_str("render.algorithm");
  addOption(render, "--tessellation-rate", o.tessellationRate,
            "Tessellation of objects drawn undisplaced: 0 = by view (curved faces split per frame "
            "until the limit surface is within 0.01 px of the chords), 1..64 = uniform Bfr rate "
            "per base-face edge",
            CLI::Range(0, 64))
      ->default_str("render.tessellation_rate");
  addOption(render, "--width", o.width, "Image width in pixels", CLI::Range(1, 16384))
      ->default_str("camera.resolution");
  addOption(render, "--height", o.height, "Image height in pixels", CLI::Range(1, 16384))
      ->default_str("camera.resolution");
  addOption(render, "--crop", o.crop,
            "X0,Y0,X1,Y1: render only the pixels X0 <= x < X1, Y0 <= y < Y1 of the image "
            "(0,0 its top-left corner); the output is that window, the same bits as in the "
            "whole image")
      ->default_str("none");
  addOption(render, "--dicing-rate", o.dicingRate, "Longest displaced micropolygon edge in pixels",
            CLI::Range(0.01f, 1000.0f))
      ->default_str("render.dicing_rate");
  addChoice(render, "--dicing-metric", o.dicingMetric,
            "isotropic (world length over the pixel footprint at its depth) or projected "
            "(foreshortened screen length; cheaper, under-resolved at grazing angles)")
      ->default_str("render.dicing_metric");
  addOption(render, "--relief-samples", o.reliefSamples,
            "Full displacement: least micropolygon edges per shortest relief wavelength, "
            "also below a pixel; 0 = pixel dicing only",
            CLI::Range(0.0f, 16.0f))
      ->default_str("render.relief_samples");
  addOption(render, "--max-micropolygons", o.maxMicropolygons,
            "Cap per frame; a frame over it is diced coarser, with a warning",
            CLI::Range(int64_t{1000}, int64_t{1} << 40))
      ->default_str("render.max_micropolygons");
  addChoice(render, "--normals", o.normals,
            "Shading normal of --algorithm displacement: bump (the paper's) or facet")
      ->default_str("render.normals");
  addOption(render, "--D", o.transitionD,
            "Transition D: pixels per shortest wavelength below which a level is not "
            "displaced",
            CLI::Range(0.0f, 1e6f))
      ->default_str("render.D");
  addOption(render, "--eps", o.transitionEps,
            "Transition eps of T = (nu - D) / (cos theta_V + eps)", CLI::Range(0.0f, 1e6f))
      ->default_str("render.eps");
  addOption(render, "--thresholds", o.thresholds,
            "Transition thresholds e1,e2,e3,e4 with e1 < e2 < 0 < e3 < e4")
      ->delimiter(',')
      ->expected(4)
      ->default_str("render.thresholds");
  render->add_flag("--false-colour,--false-color", o.falseColour,
                   "Beauty in the algorithm colours (brdf yellow, bump green, redistribution blue, "
                   "displacement red, synthesis magenta)");
  render->add_flag("--no-bump-filter", o.noBumpFilter,
                   "--algorithm bump: point-sample the slopes instead of filtering them over the "
                   "pixel footprint (Schilling)");
  render->add_flag("--no-texture-filter", o.noTextureFilter,
                   "Colour textures: the texel under each sample (bilinear, finest level) instead "
                   "of a lookup filtered over the sample's footprint");
  render->add_flag("--no-shadows", o.noShadows,
                   "No shadow rays and no relief self-shadowing (render.shadows = false)");
  addOption(render, "--frames", o.frames, "Frames A:B (inclusive) of the scene's [path]")
      ->default_str("all");
  addOption(render, "--shard", o.shard, "i/n: render only the frames f with f % n == i (for farms)")
      ->default_str("0/1");
  render->add_flag("--overwrite", o.overwrite,
                   "Re-render frames of a [path] whose EXR and PNG already exist (a still is "
                   "always written)");
  addOption(render, "--video", o.video,
            "Assemble the frames' PNGs into this video with ffmpeg (must be on the PATH)")
      ->default_str("none");
  render->add_flag("-q,--quiet", o.quiet, "No progress bar and no summary");
  return render;
}

namespace {

// A finite number as TOML writes it (TOML refuses .5 and 5.), else meso::Error naming `option`.
std::string tomlNumber(const std::string& text, const std::string& option,
                       const std::string& expected) {
  if (!finiteNumberProblem(text).empty())
    throw Error(option + ": expected " + expected + ", got \"" + text + "\"");
  return fmt::format("{:.17g}", std::strtod(text.c_str(), nullptr));
}

// "X,Y,Z" as the TOML array [X, Y, Z] (the reader checks the point), else meso::Error naming
// `option`.
std::string pointValue(const std::string& text, const std::string& option) {
  const std::string expected = "X,Y,Z (three numbers separated by commas)";
  std::string array;
  size_t pieces = 0;
  for (size_t start = 0; start <= text.size(); ++pieces) {
    const size_t comma = std::min(text.find(',', start), text.size());
    array += (array.empty() ? "" : ", ") +
             tomlNumber(text.substr(start, comma - start), option, expected);
    start = comma + 1;
  }
  if (pieces != 3) throw Error(option + ": expected " + expected + ", got \"" + text + "\"");
  return "[" + array + "]";
}

// The camera options given, by name.
std::vector<std::string> cameraOptionsGiven(const RenderCommandOptions& o) {
  std::vector<std::string> given;
  if (!o.cameraPosition.empty()) given.push_back("--camera-position");
  if (!o.lookAt.empty()) given.push_back("--look-at");
  if (!o.fov.empty()) given.push_back("--fov");
  return given;
}

}  // namespace

std::vector<SceneOverride> sceneOverrides(const RenderCommandOptions& o) {
  std::vector<SceneOverride> overrides = setOverrides(o.set);
  if (!o.cameraPosition.empty())
    overrides.push_back({.origin = "--camera-position",
                         .key = "camera.position",
                         .value = pointValue(o.cameraPosition, "--camera-position")});
  if (!o.lookAt.empty())
    overrides.push_back({.origin = "--look-at",
                         .key = "camera.look_at",
                         .value = pointValue(o.lookAt, "--look-at")});
  if (!o.fov.empty())
    overrides.push_back({.origin = "--fov",
                         .key = "camera.fov",
                         .value = tomlNumber(o.fov, "--fov", "degrees in (0, 180)")});
  return overrides;
}

void applyRenderOptions(const RenderCommandOptions& o, Scene& scene) {
  if (const std::vector<std::string> camera = cameraOptionsGiven(o);
      !camera.empty() && !scene.path.keys.empty())
    throw Error(camera.front() + ": " + scene.file.string() +
                " has a [path]: its keyframes place the camera (edit path.keys, or set their "
                "defaults with --set camera.position=... and the like)");
  if (o.spp) scene.camera.spp = *o.spp;
  if (o.threads) scene.render.threads = *o.threads;
  if (o.seed) scene.render.seed = *o.seed;
  if (o.algorithm) scene.render.algorithm = *o.algorithm;
  if (o.tessellationRate) scene.render.tessellationRate = *o.tessellationRate;
  if (o.width) scene.camera.width = *o.width;
  if (o.height) scene.camera.height = *o.height;
  if (o.dicingRate) scene.render.dicingRate = *o.dicingRate;
  if (o.dicingMetric) scene.render.dicingMetric = *o.dicingMetric;
  if (o.reliefSamples) scene.render.reliefSamples = *o.reliefSamples;
  if (o.maxMicropolygons) scene.render.maxMicropolygons = *o.maxMicropolygons;
  if (o.normals) scene.render.normals = *o.normals;
  if (o.noShadows) scene.render.shadows = false;
  TransitionSettings& t = scene.render.transition;
  if (o.transitionD) t.D = *o.transitionD;
  if (o.transitionEps) t.eps = *o.transitionEps;
  if (o.thresholds.size() == 4)
    t.e1 = o.thresholds[0], t.e2 = o.thresholds[1], t.e3 = o.thresholds[2], t.e4 = o.thresholds[3];
  validateTransitionSettings(t, "--D/--eps/--thresholds");
}

std::optional<PixelWindow> cropWindow(const RenderCommandOptions& o, const CameraSettings& camera) {
  if (o.crop.empty()) return std::nullopt;
  const std::string expected =
      "--crop: expected X0,Y0,X1,Y1 with 0 <= X0 < X1 <= " + std::to_string(camera.width) +
      " and 0 <= Y0 < Y1 <= " + std::to_string(camera.height) + " (the image is " +
      std::to_string(camera.width) + "x" + std::to_string(camera.height) + "), got " + o.crop;
  std::vector<int> v;
  for (size_t start = 0; start <= o.crop.size() && v.size() < 5;) {
    const size_t comma = std::min(o.crop.find(',', start), o.crop.size());
    v.push_back(static_cast<int>(
        parseInteger(o.crop.substr(start, comma - start), "--crop", -(1 << 30), 1 << 30)));
    start = comma + 1;
  }
  if (v.size() != 4) throw Error(expected);
  const PixelWindow w{.x0 = v[0], .y0 = v[1], .x1 = v[2], .y1 = v[3]};
  if (!(0 <= w.x0 && w.x0 < w.x1 && w.x1 <= camera.width && 0 <= w.y0 && w.y0 < w.y1 &&
        w.y1 <= camera.height))
    throw Error(expected);
  return w;
}

}  // namespace meso::app
