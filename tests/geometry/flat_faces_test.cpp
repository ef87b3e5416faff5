#include "meso/geometry/flat_faces.h"

#include "meso/core/error.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

namespace meso {
namespace {

// A bilinear grid is flat parallelograms: two triangles a face, and every barycentric hit gives
// the patch coordinates of the very point it hit.
TEST(FlatFaces, BilinearGridIsTwoTrianglesAFace) {
  const LimitSurface surface(test::grid(4), SubdivisionScheme::Bilinear);
  const std::vector<uint8_t> affine = affineFaces(surface);
  for (uint8_t a : affine) EXPECT_EQ(a, 1);
  const TessellatedMesh smooth = tessellateSmooth(surface, 8);
  EXPECT_EQ(smooth.numTriangles(), 2u * 16u);
  EXPECT_EQ(tessellateUniform(surface, 8).numTriangles(), 2u * 64u * 16u);
  for (size_t t = 0; t < smooth.numTriangles(); ++t)
    for (float b1 : {0.2f, 0.5f})
      for (float b2 : {0.1f, 0.3f}) {
        const uint32_t* v = &smooth.indices[3 * t];
        const Vec3 onTriangle = (1.0f - b1 - b2) * smooth.positions[v[0]] +
                                b1 * smooth.positions[v[1]] + b2 * smooth.positions[v[2]];
        const Vec3 limit =
            surface.evaluate(smooth.triangleFace[t], smooth.patchCoords(t, b1, b2)).P;
        EXPECT_LT(glm::length(onTriangle - limit), 1e-5f);
      }
  EXPECT_EQ(test::countOpenEdges(smooth), 16);  // the grid's border only: watertight inside
}

// Bilinear quads are decided by their corners (their twist): a sheared grid is flat everywhere; one
// raised vertex twists exactly the four faces around it, however little above float rounding.
TEST(FlatFaces, BilinearQuadsAreFlatExactlyWhereUntwisted) {
  ControlMesh mesh = test::grid(4);
  for (Vec3& p : mesh.positions) p.x += 0.3f * p.y;  // parallelograms
  for (float lift : {1e-3f, 0.5f}) {
    ControlMesh raised = mesh;
    raised.positions[2 * 5 + 2].z = lift;  // the grid's centre vertex (i = j = 2)
    const std::vector<uint8_t> affine =
        affineFaces(LimitSurface(raised, SubdivisionScheme::Bilinear));
    for (int f = 0; f < 16; ++f) {
      const int i = f % 4, j = f / 4;
      const bool aroundCentre = (i == 1 || i == 2) && (j == 1 || j == 2);
      EXPECT_EQ(affine[f], aroundCentre ? 0 : 1) << "face " << f << ", lift " << lift;
    }
  }
}

// Far from the origin the limit evaluates to within float rounding of the plane, not exactly on it:
// a ground's far faces are still flat.
TEST(FlatFaces, FlatFacesFarFromTheOriginAreFlat) {
  ControlMesh far = test::grid(4);
  for (Vec3& p : far.positions) p += Vec3(300.0f, -280.0f, 0.0f);
  for (uint8_t a : affineFaces(LimitSurface(far, SubdivisionScheme::Bilinear))) EXPECT_EQ(a, 1);
}

// A bent or curved face is not affine: a grid with one raised vertex keeps the rate on the faces
// around it (and the edges they share with flat faces), a torus everywhere.
TEST(FlatFaces, CurvedFacesKeepTheRate) {
  ControlMesh bent = test::grid(4);
  bent.positions[12].z = 0.5f;  // the centre vertex of the 5 x 5 grid
  const LimitSurface bentSurface(bent, SubdivisionScheme::Bilinear);
  const std::vector<uint8_t> affine = affineFaces(bentSurface);
  int flat = 0;
  for (uint8_t a : affine) flat += a;
  EXPECT_EQ(flat, 12);  // the four faces at the centre are bent
  const size_t bentTriangles = tessellateSmooth(bentSurface, 8).numTriangles();
  EXPECT_GT(bentTriangles, 4u * 128u);
  EXPECT_LT(bentTriangles, 16u * 128u);
  EXPECT_EQ(test::countOpenEdges(tessellateSmooth(bentSurface, 8)), 16);  // the grid's border
  const LimitSurface torus(test::torus(8, 6, 2.0f, 0.5f), SubdivisionScheme::CatmullClark);
  for (uint8_t a : affineFaces(torus)) EXPECT_EQ(a, 0);
  EXPECT_EQ(tessellateSmooth(torus, 4).numTriangles(), tessellateUniform(torus, 4).numTriangles());
}

// Undisplaced geometry honours --memory-limit: its triangles are counted before any is made, flat
// faces at two a face whatever the rate.
TEST(FlatFaces, CurvedTessellationBeyondTheMemoryLimitIsRefused) {
  const LimitSurface torus(test::torus(8, 6, 2.0f, 0.5f), SubdivisionScheme::CatmullClark);
  constexpr uint64_t kLimit = uint64_t(16) << 20;
  try {
    tessellateSmooth(torus, 64, kLimit, "torus.obj");
    ADD_FAILURE() << "48 quads at rate 64 (393 216 triangles, 36 MiB) fit in 16 MiB";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("torus.obj: render.tessellation_rate: "), std::string::npos) << what;
    EXPECT_NE(what.find("about 393216 triangles at rate 64 on 48 curved faces"), std::string::npos)
        << what;
  }
  EXPECT_EQ(tessellateSmooth(torus, 16, kLimit, "torus.obj").numTriangles(), 48u * 2u * 256u);
  const LimitSurface ground(test::grid(64), SubdivisionScheme::Bilinear);
  EXPECT_EQ(tessellateSmooth(ground, 64, kLimit, "ground.obj").numTriangles(), 2u * 64u * 64u);
}

}  // namespace
}  // namespace meso
