#include "meso/geometry/control_mesh.h"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

namespace meso {
namespace {

TEST(ControlMesh, TransformMovesPositionsAndKeepsUvs) {
  ControlMesh mesh;
  mesh.positions = {Vec3(1.0f, 2.0f, 3.0f), Vec3(0.0f)};
  mesh.uvs = {Vec2(0.25f, 0.5f)};
  Mat4 m = glm::translate(Mat4(1.0f), Vec3(1.0f, 0.0f, -1.0f));
  m = glm::scale(m, Vec3(2.0f));
  transformControlMesh(mesh, m);
  EXPECT_EQ(mesh.positions[0], Vec3(3.0f, 4.0f, 5.0f));
  EXPECT_EQ(mesh.positions[1], Vec3(1.0f, 0.0f, -1.0f));
  EXPECT_EQ(mesh.uvs[0], Vec2(0.25f, 0.5f));
}

}  // namespace
}  // namespace meso
