#include "meso/core/error.h"
#include "meso/scene/mesh_io.h"

#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace meso {
namespace {

namespace fs = std::filesystem;

class MeshIoTest : public testing::TempDirTest {
 protected:
  std::string errorOf(const fs::path& p) {
    try {
      loadControlMesh(p);
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  }
};

TEST_F(MeshIoTest, ObjWithFaceVaryingUvs) {
  // Two quads sharing an edge; the shared vertices have different uvs in each face (a seam).
  const ControlMesh m = loadControlMesh(write("a.obj",
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
      "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
      "f 1/1 2/2 3/3 4/4\nf 2/1 5/2 6/3 3/5\n"));
  ASSERT_EQ(m.positions.size(), 6u);
  ASSERT_EQ(m.faceSizes, (std::vector<int>{4, 4}));
  ASSERT_TRUE(m.hasUvs());
  ASSERT_EQ(m.uvIndices.size(), 8u);
  EXPECT_EQ(m.uvs.size(), 5u);  // identical values shared
  // Corner by corner, the face-varying value follows the face, not the vertex.
  for (size_t i = 0; i < 8; ++i) {
    const int f = static_cast<int>(i / 4), c = static_cast<int>(i % 4);
    const Vec2 expected = (f == 1 && c == 3) ? Vec2(0.5f) : Vec2(c == 1 || c == 2 ? 1.0f : 0.0f, c >= 2 ? 1.0f : 0.0f);
    EXPECT_EQ(m.uvs[m.uvIndices[i]], expected) << i;
  }
  EXPECT_EQ(m.positions[m.faceVertices[5]], Vec3(2, 0, 0));
}

TEST_F(MeshIoTest, ObjWithoutUvsPlyAndOff) {
  const ControlMesh obj = loadControlMesh(write("b.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
  EXPECT_FALSE(obj.hasUvs());
  EXPECT_EQ(obj.faceSizes, std::vector<int>{3});
  const ControlMesh off = loadControlMesh(write("c.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n"));
  EXPECT_EQ(off.faceSizes, std::vector<int>{4});
  EXPECT_EQ(off.positions[2], Vec3(1, 1, 0));
  const ControlMesh ply = loadControlMesh(write("d.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
  EXPECT_EQ(ply.faceSizes, std::vector<int>{3});
  EXPECT_EQ(ply.positions[1], Vec3(1, 0, 0));
}

TEST_F(MeshIoTest, BadMeshesAreClearErrors) {
  EXPECT_NE(errorOf(dir_ / "absent.obj").find("absent.obj: mesh file not found"), std::string::npos);
  EXPECT_NE(errorOf(write("e.obj", "")).find("e.obj: empty mesh file"), std::string::npos);
  EXPECT_NE(errorOf(write("f.obj", "v 0 0 0\nv 1 0 0\n")).find("f.obj: mesh has no faces"), std::string::npos);
  EXPECT_NE(errorOf(write("g.xyz", "1 2 3\n")).find("g.xyz: unknown mesh format"), std::string::npos);
  EXPECT_NE(errorOf(write("h.off", "OFF\n3 1 0\n0 0 0\n1 0")).find("h.off: "), std::string::npos);
  EXPECT_NE(errorOf(write("i.obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")).find("i.obj: "), std::string::npos);
  const std::string truncated = errorOf(write("j.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"));
  EXPECT_NE(truncated.find("j.ply: "), std::string::npos) << truncated;
}

}  // namespace
}  // namespace meso
