// Reads TOML scenes (docs/scene-format.md) with toml++. Every rejected value names
// FILE:LINE:COL: key: what was expected.
#include "meso/scene/scene_parser.h"

#include "meso/core/input_file.h"
#include "meso/scene/camera_path.h"
#include "meso/scene/relief_bands.h"

#include "material_reader.h"
#include "scene_overrides.h"
#include "table_reader.h"

#include <glm/gtc/matrix_transform.hpp>
#include <toml++/toml.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>

namespace meso {
namespace {

void readCamera(TableReader& r, CameraSettings& c) {
  c.position = r.vec3("position", c.position);
  c.lookAt = r.vec3("look_at", c.lookAt);
  c.up = r.vec3("up", c.up);
  c.fovY = static_cast<float>(r.number("fov", c.fovY, 0.0, 180.0, true, true));
  if (const toml::node* n = r.get("resolution")) {
    const std::vector<double> v = r.numbers(*n, "resolution", 2, 1, 16384);
    if (v[0] != std::floor(v[0]) || v[1] != std::floor(v[1]))
      r.fail(*n, "resolution", "expected two integers [width, height]");
    c.width = static_cast<int>(v[0]);
    c.height = static_cast<int>(v[1]);
  }
  c.spp = static_cast<int>(r.integer("spp", c.spp, 1, 65536));
  const Vec3 view = c.lookAt - c.position;
  const toml::node* anchor = r.get("look_at") ? r.get("look_at") : r.get("position");
  if (!std::isfinite(glm::length(view))) {
    const char* what =
        "expected a view direction look_at - position that single precision holds "
        "(coordinates below about 1e18)";
    // The key whose point is the farther out (the one that overflowed).
    const bool eye = !(glm::length(c.position) <= glm::length(c.lookAt));
    const char* key = eye ? "position" : "look_at";
    if (const toml::node* n = r.get(key)) r.fail(*n, key, what);
    throw Error(FileLoc{r.file()}, std::string("camera.") + key, what);
  }
  if (glm::length(view) < 1e-12f) {
    if (anchor) r.fail(*anchor, "look_at", "expected a point different from camera.position");
    throw Error(FileLoc{r.file()}, "camera.look_at",
                "expected a point different from camera.position");
  }
  if (glm::length(glm::cross(glm::normalize(view), c.up)) < 1e-6f) {
    const toml::node* up = r.get("up");
    if (up)
      r.fail(*up, "up", "expected a direction not parallel to the view direction (and not zero)");
    throw Error(FileLoc{r.file()}, "camera.up",
                "the default up (0, 1, 0) is parallel to the view direction: set camera.up");
  }
  r.finish();
}

Light readLight(TableReader& r) {
  Light l;
  l.type = r.choice("type", l.type);
  if (l.type == LightType::Directional) {
    l.direction = r.vec3("direction", l.direction);
    if (glm::length(l.direction) < 1e-12f)
      r.fail(*r.get("direction"), "direction", "expected a non-zero direction");
    l.direction = glm::normalize(l.direction);
  } else {
    l.position = r.vec3("position", l.position);
    l.radius = static_cast<float>(r.number("radius", l.radius, 0.0, 1e6));
  }
  l.intensity = static_cast<float>(r.number("intensity", l.intensity, 0.0, 1e12));
  l.colour = r.colour("colour", l.colour);
  r.finish();
  return l;
}

// A [[lights]] table of type "environment": a map file or a uniform sky (docs/environment.md).
EnvironmentDecl readEnvironment(TableReader& r, const std::filesystem::path& base) {
  EnvironmentDecl e;
  e.loc = r.tableLoc();
  r.choice("type", LightType::Environment);
  if (r.get("environment")) e.file = readablePath(r, "environment", base);
  e.space = r.choice("colour_space", e.space);
  e.colour = r.colour("colour", e.colour);
  e.intensity = static_cast<float>(r.number("intensity", e.intensity, 0.0, 1e12));
  e.rotation = static_cast<float>(r.number("rotation", e.rotation, -1e6, 1e6));
  if (const toml::node* n = r.get("up")) {
    e.up = r.vec3("up", e.up);
    if (!(glm::length(e.up) > 1e-12f) || !isFinite(e.up))
      r.fail(*n, "up", "expected a non-zero direction");
    e.up = glm::normalize(e.up);
  }
  r.finish();
  return e;
}

Mat4 readTransform(TableReader& r) {
  const Vec3 t = r.vec3("translate", Vec3(0.0f));
  const Vec3 rot = r.vec3("rotate", Vec3(0.0f), -1e6, 1e6);
  Vec3 s(1.0f);
  if (const toml::node* n = r.get("scale")) {
    if (n->is_number()) {
      s = Vec3(static_cast<float>(r.checkedNumber(*n, "scale", -1e12, 1e12, false, false)));
    } else {
      const std::vector<double> v = r.numbers(*n, "scale", 3, -1e12, 1e12);
      s = Vec3(static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]));
    }
    if (s.x == 0.0f || s.y == 0.0f || s.z == 0.0f)
      r.fail(*n, "scale", "expected non-zero scale factors");
  }
  Mat4 m = glm::translate(Mat4(1.0f), t);
  m = glm::rotate(m, radians(rot.z), Vec3(0, 0, 1));
  m = glm::rotate(m, radians(rot.y), Vec3(0, 1, 0));
  m = glm::rotate(m, radians(rot.x), Vec3(1, 0, 0));
  return glm::scale(m, s);
}

Object readObject(TableReader& r, const std::vector<Material>& materials,
                  const std::filesystem::path& base) {
  Object o;
  const toml::node* mesh = r.get("mesh");
  if (!mesh)
    throw Error(r.tableLoc(), r.prefix() + "mesh",
                "every object needs a mesh file (OBJ, PLY or OFF)");
  o.loc = r.loc(*mesh);
  o.mesh = readablePath(r, "mesh", base);
  o.scheme = r.choice("scheme", o.scheme);
  if (const std::optional<std::string> name = r.string("material")) {
    auto it = std::find_if(materials.begin(), materials.end(),
                           [&](const Material& m) { return m.name == *name; });
    if (it == materials.end())
      r.fail(*r.get("material"), "material", "no material named \"" + *name + "\"");
    o.material = static_cast<int>(it - materials.begin());
  } else if (materials.size() > 1) {
    throw Error(o.loc, r.prefix() + "material",
                "expected a material name: the scene has more than one material");
  }
  o.transform = readTransform(r);
  r.finish();
  return o;
}

void readRender(TableReader& r, RenderSettings& s, const std::filesystem::path& base) {
  s.algorithm = r.choice("algorithm", s.algorithm);
  s.seed = static_cast<uint64_t>(r.integer("seed", 0, 0, INT64_MAX));
  s.threads = static_cast<int>(r.integer("threads", s.threads, 0, 1024));
  s.tessellationRate = static_cast<int>(r.integer("tessellation_rate", s.tessellationRate, 0, 64));
  s.background = r.colour("background", s.background);
  s.transition.D = static_cast<float>(r.number("D", s.transition.D, 0.0, 1e6));
  s.transition.eps = static_cast<float>(r.number("eps", s.transition.eps, 0.0, 1e6));
  if (const toml::node* n = r.get("thresholds")) {
    const std::vector<double> v = r.numbers(*n, "thresholds", 4, -1e6, 1e6);
    const float e1 = static_cast<float>(v[0]), e2 = static_cast<float>(v[1]),
                e3 = static_cast<float>(v[2]), e4 = static_cast<float>(v[3]);
    if (!thresholdsOrdered(e1, e2, e3, e4))
      r.fail(*n, "thresholds", std::string("expected [e1, e2, e3, e4] with ") + kThresholdOrder);
    s.transition.e1 = e1, s.transition.e2 = e2, s.transition.e3 = e3, s.transition.e4 = e4;
  }
  s.dicingRate = static_cast<float>(r.number("dicing_rate", s.dicingRate, 0.01, 1000.0));
  s.dicingMetric = r.choice("dicing_metric", s.dicingMetric);
  s.acrossViewCap = static_cast<float>(r.number("across_view_cap", s.acrossViewCap, 0.05, 1.0));
  s.reliefSamples = static_cast<float>(r.number("relief_samples", s.reliefSamples, 0.0, 16.0));
  s.texelSamples = static_cast<float>(r.number("texel_samples", s.texelSamples, 0.0, 16.0));
  s.maxMicropolygons = r.integer("max_micropolygons", s.maxMicropolygons, 1000, int64_t{1} << 40);
  s.normals = r.choice("normals", s.normals);
  s.shadows = r.boolean("shadows", s.shadows);
  s.lightSamples =
      static_cast<int>(r.integer("light_samples", s.lightSamples, 1, kMaxLightSamples));
  if (const std::optional<std::string> c = r.string("cache_dir"))
    s.cacheDir = std::filesystem::path(*c).is_absolute() ? std::filesystem::path(*c) : base / *c;
  if (const toml::table* t = r.subtable("tables")) {
    TableReader tr(*t, r.prefix() + "tables.", r.file());
    TableResolution& q = s.tables;
    q.thetaVBins = static_cast<int>(tr.integer("theta_v_bins", q.thetaVBins, 2, 90));
    q.thetaNBins = static_cast<int>(tr.integer("theta_n_bins", q.thetaNBins, 4, 1024));
    q.phiBins = static_cast<int>(tr.integer("phi_bins", q.phiBins, 4, 1024));
    q.phiVBins = static_cast<int>(tr.integer("phi_v_bins", q.phiVBins, 1, 64));
    q.azimuths = static_cast<int>(tr.integer("azimuths", q.azimuths, 1, 1024));
    q.raysPerView = static_cast<int>(tr.integer("rays_per_view", q.raysPerView, 16, 1 << 22));
    q.shadowRays = static_cast<int>(tr.integer("shadow_rays", q.shadowRays, 16, 1 << 22));
    q.meshResolution = static_cast<int>(tr.integer("mesh_resolution", q.meshResolution, 8, 4096));
    q.brdfThetaL = static_cast<int>(tr.integer("brdf_theta_l", q.brdfThetaL, 2, 512));
    q.brdfPhi = static_cast<int>(tr.integer("brdf_phi", q.brdfPhi, 2, 512));
    q.variant = tr.choice("variant", q.variant);
    q.metricStep = static_cast<float>(tr.number("metric_step", q.metricStep, 0.01, 4.0));
    q.deriveClasses = tr.boolean("derive_classes", q.deriveClasses);
    q.frameViews = tr.boolean("frame_views", q.frameViews);
    tr.finish();
  }
  r.finish();
}

// What makes a camera unusable (empty when it is fine): its eye on its look_at point, a view
// direction that single precision cannot hold, or an up direction along the view.
std::string cameraProblem(const CameraSettings& c) {
  const Vec3 view = c.lookAt - c.position;
  const float length = glm::length(view);
  if (!isFinite(c.position) || !isFinite(c.lookAt) || !std::isfinite(length))
    return "the view direction look_at - position is not finite in single precision";
  if (!(length > 1e-12f)) return "the camera is at its look_at point";
  const float side = glm::length(glm::cross(view / length, c.up));
  if (!(side >= 1e-6f)) return "the up direction is parallel to the view direction (or zero)";
  return {};
}

void readPath(TableReader& r, PathSettings& p, const CameraSettings& camera) {
  const toml::node* frames = r.get("frames");
  const toml::node* fps = r.get("fps");
  for (const toml::table* t : r.tableArray("keys")) {
    TableReader k(*t, "path.keys.", r.file());
    CameraKeyframe key;
    key.time = static_cast<float>(k.number("time", 0.0, -1e9, 1e9));
    if (!p.keys.empty() && !(key.time > p.keys.back().time))
      k.fail(*k.get("time"), "time", "expected keyframe times to strictly increase");
    key.position = k.vec3("position", camera.position);
    key.lookAt = k.vec3("look_at", camera.lookAt);
    key.up = k.vec3("up", camera.up);
    key.fovY = static_cast<float>(k.number("fov", camera.fovY, 0.0, 180.0, true, true));
    if (glm::length(key.lookAt - key.position) < 1e-12f)
      throw Error(FileLoc{r.file(), static_cast<int>(t->source().begin.line), 1},
                  "path.keys.look_at", "expected a point different from the keyframe's position");
    k.finish();
    p.keys.push_back(key);
  }
  if (p.keys.empty())
    throw Error(FileLoc{r.file()}, "path.keys",
                "a [path] needs at least one [[path.keys]] keyframe");
  if (frames && fps)
    r.fail(*fps, "fps", "give either path.frames or path.fps with path.duration, not both");
  if (fps) {
    const double rate = r.number("fps", 24, 0.0, 1000.0, true);
    p.fps = rate;
    const double span = r.number("duration", p.keys.back().time - p.keys.front().time, 0.0, 1e6);
    p.frames = std::max(1, static_cast<int>(std::lround(rate * span)) + 1);
  } else {
    p.frames = static_cast<int>(r.integer("frames", 48, 1, 1000000));
    r.get("duration");
  }
  // Keyframes that are fine each can still interpolate to a frame that is not (a path through its
  // look_at point, or over it with the up along the view): refuse it here, not mid-render.
  const CameraPath path(p.keys);
  for (int i = 0; i < p.frames; ++i) {
    const CameraSettings c = path.frame(i, p.frames, camera);
    if (const std::string problem = cameraProblem(c); !problem.empty()) {
      const float f =
          p.frames > 1 ? static_cast<float>(i) / static_cast<float>(p.frames - 1) : 0.0f;
      const std::string at =
          fmt::format("{:.6g}", path.startTime() + f * (path.endTime() - path.startTime()));
      const toml::node* keys = r.get("keys");
      throw Error(FileLoc{r.file(), keys ? static_cast<int>(keys->source().begin.line) : 0,
                          keys ? static_cast<int>(keys->source().begin.column) : 0},
                  "path.keys",
                  "frame " + std::to_string(i) + " (time " + at + ") is not a usable camera: " +
                      problem + "; move or add keyframes so the path avoids it");
    }
  }
  r.finish();
}

// Each camera sample is shaded with the scene's lights and the environment's light samples, each
// with its own shadow factor: at most kMaxSampleLights of them.
void checkSampleLights(TableReader& r, const Scene& scene) {
  if (!scene.environment) return;
  const size_t total = scene.lights.size() + static_cast<size_t>(scene.render.lightSamples);
  if (total <= static_cast<size_t>(kMaxSampleLights)) return;
  const std::string what =
      "the environment's " + std::to_string(scene.render.lightSamples) + " light samples and " +
      std::to_string(scene.lights.size()) + " other lights make " + std::to_string(total) +
      " lights per camera sample; at most " + std::to_string(kMaxSampleLights) +
      " are shaded with shadows: lower render.light_samples";
  const toml::table* render = r.subtable("render");
  if (render)
    if (const toml::node* n = render->get("light_samples"))
      throw Error(r.loc(*n), "render.light_samples", what);
  throw Error(scene.environment->loc, "lights", what);
}

void readTop(const toml::table& top, Scene& scene) {
  const std::string file = scene.file.string();
  const std::filesystem::path base = scene.file.parent_path();
  TableReader r(top, "", file);
  if (const toml::table* c = r.subtable("camera")) {
    TableReader cr(*c, "camera.", file);
    readCamera(cr, scene.camera);
  }
  for (const toml::table* t : r.tableArray("lights")) {
    TableReader lr(*t, "lights.", file);
    if (lr.choice("type", LightType::Directional) != LightType::Environment) {
      scene.lights.push_back(readLight(lr));
      continue;
    }
    EnvironmentDecl e = readEnvironment(lr, base);
    if (scene.environment)
      throw Error(e.loc, "lights.type",
                  "at most one environment light per scene (the first is at line " +
                      std::to_string(scene.environment->loc.line) + ")");
    scene.environment = std::move(e);
  }
  for (const toml::table* t : r.tableArray("materials")) {
    TableReader mr(*t, "materials.", file);
    Material m = readMaterial(mr, base);
    for (const Material& other : scene.materials)
      if (other.name == m.name)
        throw Error(m.loc, "materials.name", "duplicate material name \"" + m.name + "\"");
    scene.materials.push_back(std::move(m));
  }
  if (scene.materials.empty()) {
    Material fallback;
    fallback.name = "default";
    scene.materials.push_back(fallback);
  }
  for (const toml::table* t : r.tableArray("objects")) {
    TableReader orr(*t, "objects.", file);
    scene.objects.push_back(readObject(orr, scene.materials, base));
  }
  if (scene.objects.empty())
    throw Error(FileLoc{file}, "objects", "expected at least one [[objects]] entry with a mesh");
  if (const toml::table* t = r.subtable("render")) {
    TableReader rr(*t, "render.", file);
    readRender(rr, scene.render, base);
  }
  if (const toml::table* t = r.subtable("path")) {
    TableReader pr(*t, "path.", file);
    readPath(pr, scene.path, scene.camera);
  }
  checkSampleLights(r, scene);
  r.finish();
}

}  // namespace

Scene parseScene(std::string_view text, const std::filesystem::path& file,
                 std::span<const SceneOverride> overrides) {
  Scene scene;
  scene.file = file;
  toml::table top;
  try {
    top = toml::parse(text, file.string());
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw Error(FileLoc{file.string(), static_cast<int>(b.line), static_cast<int>(b.column)}, "",
                std::string(e.description()));
  }
  applySceneOverrides(top, overrides);
  readTop(top, scene);
  return scene;
}

Scene loadScene(const std::filesystem::path& file, std::span<const SceneOverride> overrides,
                uint64_t memoryLimitBytes) {
  Scene scene = parseScene(readInputFile(file, "scene", kMaxSceneBytes), file, overrides);
  expandImageBands(scene, memoryLimitBytes);
  return scene;
}

}  // namespace meso
