// What a scene file describes: camera, lights, materials, objects and render settings.
#pragma once

#include "meso/core/error.h"
#include "meso/core/math.h"
#include "meso/core/texture_lookup.h"  // ColourSpace
#include "meso/geometry/control_mesh.h"
#include "meso/scene/choices.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace meso {

struct CameraSettings {
  Vec3 position{0.0f, 0.0f, 5.0f};
  Vec3 lookAt{0.0f};
  Vec3 up{0.0f, 1.0f, 0.0f};
  float fovY = 40.0f;  // vertical field of view, degrees, in (0, 180)
  int width = 640;
  int height = 360;
  int spp = 4;  // samples per pixel; rounded up to a square number of strata by the renderer
};

struct Light {
  LightType type = LightType::Directional;
  Vec3 direction{0.0f, 0.0f, -1.0f};  // directional: the direction the light travels (normalized)
  Vec3 position{0.0f};                // point: where the light is
  float intensity = 1.0f;  // directional: irradiance at normal incidence; point: at distance 1
  Vec3 colour{1.0f};
  // Point lights: the radius of the sphere that emits (0: a point). Shading takes the light from
  // its centre (a uniformly emitting sphere lights what it wholly sees as a point of the same
  // power); shadow rays aim at points of the sphere, so shadows are soft.
  float radius = 0.0f;
};

// A [[lights]] table of type "environment" (docs/environment.md): radiance from every direction,
// a latitude-longitude map or a uniform sky. Shading integrates it by importance-sampled
// directional lights, render.light_samples per camera sample (render/environment_map.h).
struct EnvironmentDecl {
  FileLoc loc;                 // the [[lights]] table
  std::filesystem::path file;  // the map (resolved against the scene's folder); empty: uniform
  ColourSpace space = ColourSpace::Auto;  // how the map's values are encoded
  Vec3 colour{1.0f};       // the uniform sky's radiance; with a map, a tint of its texels
  float intensity = 1.0f;  // scales the radiance
  float rotation = 0.0f;   // degrees about `up` (right-handed: counter-clockwise seen from above)
  Vec3 up{0.0f, 1.0f, 0.0f};  // the map's top row (unit)
};

// One relief level as declared in the scene (used by the relief and appearance work).
// The most relief levels one material may declare (meso::kMaxReliefLevels of
// relief/level_frames.h).
inline constexpr int kMaxMaterialReliefLevels = 8;

struct ReliefLevelDecl {
  FileLoc loc;
  std::filesystem::path height;  // image file, empty for procedural noise
  ReliefSource source = ReliefSource::Image;
  float amplitude = 0.0f;  // world units
  float scale = 1.0f;      // tiling scale S: the height table repeats every 1/S in u and v;
                           // solid relief: lattice cells per unit of length at octave 0
  float freq = 0.0f;       // highest frequency, cycles per unit of u (0: measured or known)
  // The height value that stays on the surface: displacement is amplitude * (h - midlevel). Empty:
  // the height source's mean, so smooth-surface renderers draw the relief's mean plane.
  std::optional<float> midlevel;
  // Procedural noise parameters.
  int octaves = 4;
  float lacunarity = 2.0f;
  float gain = 0.5f;
  uint64_t seed = 0;
  bool periodic = true;
  // Solid relief: its noise lives in world space rather than in the object's own (before the
  // object's transform).
  bool worldSpace = false;
  // Octaves firstOctave .. octaves - 1 only: one level of a relief whose `split_octaves` made a
  // level of each octave (the scene reader expands it; docs/scene-format.md).
  int firstOctave = 0;
  // Height images: the octave bands it is split into (key `bands`; 0: as many as the image holds,
  // weak ones merged; 1: the image is one level), and which of them this level sums: bands
  // bandFirst..bandLast of bandCount (the scene reader expands an image into one level per group).
  int bands = 0;
  int bandCount = 1;
  int bandFirst = 0;
  int bandLast = 0;
};

// [materials.ndf]: the finest level, fractal NDF synthesis (Kautz et al. 2001; docs/synthesis.md).
struct NdfDecl {
  bool present = false;
  FileLoc loc;
  NdfType type = NdfType::Beckmann;
  Vec2 alpha{0.3f};             // beckmann roughness (alpha_x, alpha_y); equal for isotropic
  float angle = 0.0f;           // degrees: the alpha_x axis, measured from P_u towards P_v
  float exponent = 40.0f;       // blinn-phong
  std::filesystem::path image;  // tabulated: NDF over (n.x, n.y) of the hemisphere
  float scale = 0.0f;  // turbulence cycles per unit of u at octave 0 (0: from the relief or 16)
  int octaves = 8;     // most turbulence octaves
  float lacunarity = 2.0f;
  float gain = 0.5f;
  uint64_t seed = 0;
  bool lambert = true;  // keep the kd (L.N) term
};

// What the local model reflects at a point: ka + sum over lights of kd (L.N) + ks (H.N)^phong.
// Every renderer shades with one; a material's are its constants, or per sample its colour
// textures' filtered values (render/colour_textures.h).
struct Reflectance {
  Vec3 ka{0.0f};
  Vec3 kd{0.8f};
  Vec3 ks{0.0f};
  float phong = 20.0f;  // exponent n of (H.N)^n
};

// A colour image standing for kd or ks (docs/scene-format.md): looked up through OpenImageIO's
// TextureSystem at the surface's (u, v), filtered over the pixel's footprint.
struct ColourTexture {
  std::filesystem::path file;  // empty: the constant colour
  FileLoc loc;
  ColourSpace space = ColourSpace::Auto;  // how its values are encoded
};

struct Material : Reflectance {
  std::string name;
  FileLoc loc;
  ColourTexture kdTexture, ksTexture;
  std::vector<ReliefLevelDecl> relief;
  NdfDecl ndf;
};

struct Object {
  FileLoc loc;
  std::filesystem::path mesh;  // resolved against the scene file's folder
  SubdivisionScheme scheme = SubdivisionScheme::CatmullClark;
  Mat4 transform{1.0f};
  int material = 0;  // index into Scene::materials
};

// D, eps and the thresholds e1 < e2 < 0 < e3 < e4 of DESIGN.md section 3 (Becker & Max eq. 10).
struct TransitionSettings {
  float D = 2.0f;  // the speed-for-accuracy knob (the paper's c), in pixels per shortest wavelength
  float eps = 0.1f;  // keeps T finite at the silhouette (cos theta_V = 0)
  float e1 = -1.0f;
  float e2 = -0.3f;
  float e3 = 0.3f;
  float e4 = 1.0f;
};

// The one check of the thresholds' order, kThresholdOrder (scene reader, CLI and trade alike).
inline constexpr const char* kThresholdOrder = "e1 < e2 < 0 < e3 < e4";
inline bool thresholdsOrdered(float e1, float e2, float e3, float e4) {
  return e1 < e2 && e2 < 0.0f && 0.0f < e3 && e3 < e4;
}

// [render.tables]: resolutions of the appearance tables (DESIGN.md section 4). Part of the cache
// key.
struct TableResolution {
  int thetaVBins = 16;       // view slices of the visible-normal histogram and the BRDF
  int thetaNBins = 96;       // normal polar bins
  int phiBins = 32;          // normal azimuth bins
  int phiVBins = 16;         // view azimuth slices (1: isotropic tables, the paper's)
  int azimuths = 32;         // view azimuths traced per slice
  int raysPerView = 2048;    // rays per (theta_V, phi_V)
  int shadowRays = 128;      // visible hits per slice of the self-shadowing table
  int meshResolution = 192;  // quads per tile side of the traced relief
  int brdfThetaL = 16;       // BRDF nodes over theta_L
  int brdfPhi = 16;          // BRDF nodes over |phi_{V-L}|
  RedistributionVariant variant = RedistributionVariant::Conditional;  // redistribution maps
  // Spacing of the metric classes (docs/metric.md) in octaves of length per unit of u: a surface
  // whose |P_u x P_v| varies gets one table set per step over its range.
  float metricStep = 0.25f;
  // Metric classes derive their histograms from one traced tile per level (false: each traces).
  bool deriveClasses = true;
  // The coarsest level's BRDF and self-shadowing tables only on the theta_V rows the scene's
  // frames can look up (false: every row; docs/tables.md).
  bool frameViews = true;
};

// render.light_samples: at most this many per camera sample.
inline constexpr int kMaxLightSamples = 64;
// The most lights one camera sample is shaded with, each with its own shadow factor (the scene's
// directional and point lights and its environment's light samples together; render/shading.h).
inline constexpr int kMaxSampleLights = 80;

struct RenderSettings {
  Algorithm algorithm = Algorithm::Auto;
  uint64_t seed = 0;
  int threads = 0;  // 0: all cores
  // Tessellation of objects drawn undisplaced: 0 (by view) splits each mesh edge of a curved face,
  // per frame, until the limit surface is within DicingSettings::coarseTolerance pixels of its
  // chords (faces out of view: one segment, or none where they cannot shadow the view); 1..64 is
  // a uniform Bfr rate (segments per base-face edge), built once. Objects whose every face is flat
  // (an affine image of its patch coordinates) get two triangles a face either way.
  int tessellationRate = 0;
  Vec3 background{0.0f};
  TransitionSettings transition;
  float dicingRate = 1.0f;  // micropolygon edge length in pixels where displaced
  DicingMetric dicingMetric = DicingMetric::Isotropic;  // how that length is measured
  // The hybrid: the share of a face's texel cap that edges running across a grazing view keep
  // (DicingSettings::acrossViewCap; 1: the whole cap both ways, as full displacement).
  float acrossViewCap = 0.5f;
  // Full displacement: at least this many micropolygon edges per shortest wavelength of the
  // finest relief level wherever it is diced, also where that is below a pixel (0 = off).
  float reliefSamples = 4.0f;
  // Full displacement: at most this many edges per texel of a height image (0: reliefSamples / 4,
  // at least 1).
  float texelSamples = 0.0f;
  int64_t maxMicropolygons =
      80000000;  // per frame (about 8 GiB); more coarsens dicing with a warning
  ShadingNormals normals = ShadingNormals::Bump;  // shading normal on displaced geometry
  // Macro shadows (occlusion rays towards each light) and the relief's self-shadowing in the
  // tables and in T (DESIGN.md section 6, docs/shadows.md). false: exactly the unshadowed images.
  bool shadows = true;
  // Directions sampled from the environment (Scene::environment) for each camera sample: each is a
  // directional light of that sample (docs/environment.md).
  int lightSamples = 16;
  std::filesystem::path cacheDir;  // table cache folder; empty: TableCache::defaultFolder()
  TableResolution tables;
};

// One keyframe of a camera path (see scene/camera_path.h).
struct CameraKeyframe {
  float time = 0.0f;  // seconds, strictly increasing along the path
  Vec3 position{0.0f};
  Vec3 lookAt{0.0f};
  Vec3 up{0.0f, 1.0f, 0.0f};
  float fovY = 40.0f;
};

// A fly-through: frames spread evenly over the keyframes' time span, ends included.
struct PathSettings {
  std::vector<CameraKeyframe> keys;  // empty: a still image from [camera]
  int frames = 0;
  double fps = 24.0;  // for --video
};

struct Scene {
  std::filesystem::path file;  // the scene file, for messages
  CameraSettings camera;
  std::vector<Light> lights;                   // directional and point lights
  std::optional<EnvironmentDecl> environment;  // at most one
  std::vector<Material> materials;
  std::vector<Object> objects;
  RenderSettings render;
  PathSettings path;
};

}  // namespace meso
