// `meso render`'s options: registered with CLI11 (each with its default in --help) and applied to
// the scene after it is read, each checked and named in errors.
#pragma once

#include "meso/render/integrator.h"
#include "meso/scene/choices.h"
#include "meso/scene/scene.h"
#include "meso/scene/scene_parser.h"

#include <CLI/CLI.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace meso::app {

struct RenderCommandOptions {
  std::filesystem::path scene;
  std::filesystem::path output;     // .exr; empty: out/<scene stem>.exr
  std::filesystem::path statsFile;  // empty: none
  std::vector<std::string> set;     // --set KEY=VALUE, in order
  std::string cameraPosition;       // --camera-position X,Y,Z: camera.position
  std::string lookAt;               // --look-at X,Y,Z: camera.look_at
  std::string fov;                  // --fov DEG: camera.fov
  std::optional<int> spp;
  std::optional<int> threads;
  std::optional<uint64_t> seed;
  std::optional<Algorithm> algorithm;
  std::optional<int> tessellationRate;
  std::optional<int> width, height;
  std::optional<float> dicingRate;
  std::optional<DicingMetric> dicingMetric;
  std::optional<float> reliefSamples;
  std::optional<int64_t> maxMicropolygons;
  std::optional<ShadingNormals> normals;
  std::optional<float> transitionD, transitionEps;
  std::vector<float> thresholds;  // e1,e2,e3,e4; empty: the scene's
  std::string crop;               // "X0,Y0,X1,Y1"; empty: the whole image
  bool falseColour = false;
  bool noTextureFilter = false;  // colour textures: point lookups instead of filtered ones
  bool noBumpFilter = false;     // --algorithm bump: point-sampled slopes instead of Schilling's
  bool noShadows = false;        // render.shadows = false
  bool quiet = false;
  std::string frames;           // "A:B" (inclusive) or "A"; empty: every frame of the path
  std::string shard;            // "i/n": render frames f with f % n == i
  bool overwrite = false;       // re-render frames already complete on disk
  std::filesystem::path video;  // assemble the frames' PNGs with ffmpeg
};

// Adds the `render` subcommand and its options (writing into `o`).
CLI::App* addRenderOptions(CLI::App& cli, RenderCommandOptions& o);

// The options the scene reader applies (SceneOverride): every --set in order, then
// --camera-position,
// --look-at and --fov as camera.position, camera.look_at and camera.fov. Throws meso::Error naming
// the option when an X,Y,Z is not three numbers.
std::vector<SceneOverride> sceneOverrides(const RenderCommandOptions& o);

// The options that override scene keys, applied to `scene` and checked (meso::Error naming the
// option). The camera options are refused on a scene with a [path]: its keyframes place the camera.
void applyRenderOptions(const RenderCommandOptions& o, Scene& scene);

// --crop as a window of the scene's image (after applyRenderOptions: --width and --height count);
// none without --crop. Throws meso::Error naming --crop unless 0 <= X0 < X1 <= width and
// 0 <= Y0 < Y1 <= height.
std::optional<PixelWindow> cropWindow(const RenderCommandOptions& o, const CameraSettings& camera);

}  // namespace meso::app
