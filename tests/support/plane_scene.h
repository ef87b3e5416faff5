// Scenes of a relief plane for the render tests: a square in z = 0 (one bilinear quad), one
// directional light, one material, the camera's up +z and a table cache folder of this process.
#pragma once

#include "meso/scene/scene.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

namespace meso::testing {

// Files and folders this test process made in the system temporary folder, removed when it exits.
class ProcessTemporaries {
 public:
  static std::filesystem::path add(std::filesystem::path p) {
    instance().paths_.push_back(p);
    return p;
  }
  ~ProcessTemporaries() {
    std::error_code ec;
    for (const std::filesystem::path& p : paths_) std::filesystem::remove_all(p, ec);
  }

 private:
  static ProcessTemporaries& instance() {
    static ProcessTemporaries t;
    return t;
  }
  std::vector<std::filesystem::path> paths_;
};

// A square [-half, half]^2 in z = 0 with uv running from uvLow to uvHigh across it, written once
// per process (ctest runs tests in parallel processes) under a name made from `tag`.
inline std::filesystem::path writePlaneObj(const std::string& tag, float half, float uvLow,
                                           float uvHigh) {
  const std::filesystem::path file =
      ProcessTemporaries::add(std::filesystem::temp_directory_path() /
                              ("meso_" + tag + "_plane_" + std::to_string(::getpid()) + ".obj"));
  std::ofstream out(file);
  out << "v " << -half << " " << -half << " 0\nv " << half << " " << -half << " 0\nv " << half
      << " " << half << " 0\nv " << -half << " " << half << " 0\nvt " << uvLow << " " << uvLow
      << "\nvt " << uvHigh << " " << uvLow << "\nvt " << uvHigh << " " << uvHigh << "\nvt " << uvLow
      << " " << uvHigh << "\nf 1/1 2/2 3/3 4/4\n";
  return file;
}

inline ReliefLevelDecl noiseLevel(float amplitude, float scale, int octaves = 2) {
  ReliefLevelDecl d;
  d.source = ReliefSource::Noise;
  d.octaves = octaves;
  d.amplitude = amplitude;
  d.scale = scale;
  return d;
}

// A solid relief level (3-D noise, docs/solid-relief.md) of `cells` lattice cells per unit.
inline ReliefLevelDecl solidLevel(float amplitude, float cells, int octaves = 3,
                                  uint64_t seed = 0) {
  ReliefLevelDecl d;
  d.source = ReliefSource::Solid;
  d.octaves = octaves;
  d.amplitude = amplitude;
  d.scale = cells;
  d.seed = seed;
  return d;
}

// The plane `obj` with `material`, lit from `lightDirection` (the direction light travels);
// the camera still needs its position, look-at, size, field of view and samples.
inline Scene planeScene(const std::filesystem::path& obj, const std::string& algorithm,
                        const Material& material, const Vec3& lightDirection,
                        const std::string& tag) {
  Scene s;
  s.camera.up = {0.0f, 0.0f, 1.0f};
  Light l;
  l.direction = glm::normalize(lightDirection);
  s.lights = {l};
  s.materials = {material};
  Object o;
  o.mesh = obj;
  o.scheme = SubdivisionScheme::Bilinear;
  s.objects = {o};
  s.render.algorithm = *parseChoice<Algorithm>(algorithm);
  s.render.cacheDir =
      ProcessTemporaries::add(std::filesystem::temp_directory_path() /
                              ("meso_" + tag + "_cache_" + std::to_string(::getpid())));
  return s;
}

}  // namespace meso::testing
