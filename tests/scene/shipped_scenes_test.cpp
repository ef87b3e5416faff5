// Every scene shipped in scenes/ loads, with its meshes, and means what its header says: objects
// with materials, lights, a camera that sees something, and a path of at least two keys where it
// has one. A scene broken by an edit fails here, not in front of a user.
#include "meso/scene/mesh_io.h"
#include "meso/scene/scene_parser.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <set>

namespace meso {
namespace {

namespace fs = std::filesystem;

TEST(ShippedScenes, EveryOneLoadsWithItsMeshes) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(fs::path(MESO_SOURCE_DIR) / "scenes")) {
    if (e.path().extension() != ".toml") continue;
    SCOPED_TRACE(e.path().string());
    names.insert(e.path().filename().string());
    const Scene s = loadScene(e.path());
    ASSERT_FALSE(s.objects.empty());
    EXPECT_TRUE(!s.lights.empty() || s.environment);
    EXPECT_GT(s.camera.width, 0);
    EXPECT_GT(s.camera.height, 0);
    for (const Object& o : s.objects) {
      ASSERT_LT(static_cast<size_t>(o.material), s.materials.size());
      EXPECT_GT(loadControlMesh(o.mesh).numFaces(), 0) << o.mesh;
    }
    if (!s.path.keys.empty()) {
      EXPECT_GE(s.path.keys.size(), 2u);
      EXPECT_GE(s.path.frames, 2);
    }
  }
  // The README's scenes: a rename or a deletion shows here.
  for (const char* n : {"default.toml", "default_flight.toml", "torus_floor.toml", "terrain.toml",
                        "terrain_flight.toml", "flythrough.toml", "zoom.toml", "default_sky.toml"})
    EXPECT_EQ(names.count(n), 1u) << n;
}

// The default scene is the one the README describes: relief on both materials, both lights, and the
// low camera over the wide floor.
TEST(ShippedScenes, DefaultIsTheTorusOnTheWideFloorSeenFromLowDown) {
  const Scene s = loadScene(fs::path(MESO_SOURCE_DIR) / "scenes/default.toml");
  ASSERT_EQ(s.objects.size(), 2u);
  for (const Material& m : s.materials) EXPECT_FALSE(m.relief.empty()) << m.name;
  EXPECT_EQ(s.lights.size(), 2u);
  EXPECT_LT(s.camera.position.y, 1.5f);
  EXPECT_EQ(s.camera.width, 640);
  EXPECT_EQ(s.camera.height, 360);
}

}  // namespace
}  // namespace meso
