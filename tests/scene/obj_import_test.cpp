// OBJ files are read from their checked text and handed to OpenMesh's importer: the control mesh
// must be the one OpenMesh's own OBJ reader makes of the same file (positions, faces, the extra
// vertices of non-manifold faces, and each corner's (u, v)).
#include "meso/core/error.h"
#include "meso/core/rng.h"
#include "meso/scene/mesh_io.h"
#include "meso/scene/mesh_text_check.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

namespace meso {
namespace {

// The control mesh as OpenMesh's OBJ reader gives it: positions, faces, and per corner the (u, v)
// of its halfedge (empty without texture coordinates).
struct Reference {
  std::vector<Vec3> positions;
  std::vector<int> faceSizes, faceVertices;
  std::vector<Vec2> cornerUvs;
};

Reference readWithOpenMesh(const std::string& text) {
  using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<>;
  PolyMesh mesh;
  mesh.request_halfedge_texcoords2D();
  OpenMesh::IO::Options options = OpenMesh::IO::Options::FaceTexCoord;
  std::istringstream stream(text);
  omerr().disable();
  EXPECT_TRUE(OpenMesh::IO::read_mesh(mesh, stream, ".obj", options));
  Reference r;
  for (const auto& v : mesh.vertices()) {
    const auto p = mesh.point(v);
    r.positions.emplace_back(p[0], p[1], p[2]);
  }
  for (const auto& f : mesh.faces()) {
    int n = 0;
    for (const auto& h : mesh.fh_range(f)) {
      r.faceVertices.push_back(mesh.to_vertex_handle(h).idx());
      if (options.check(OpenMesh::IO::Options::FaceTexCoord)) {
        const auto t = mesh.texcoord2D(h);
        r.cornerUvs.emplace_back(t[0], t[1]);
      }
      ++n;
    }
    r.faceSizes.push_back(n);
  }
  return r;
}

void expectSameMesh(const std::string& text, const std::string& what) {
  SCOPED_TRACE(what);
  const Reference r = readWithOpenMesh(text);
  const ControlMesh m = parseControlMesh(text, "test.obj");
  ASSERT_EQ(m.positions.size(), r.positions.size());
  for (size_t i = 0; i < r.positions.size(); ++i) ASSERT_EQ(m.positions[i], r.positions[i]) << i;
  ASSERT_EQ(m.faceSizes, r.faceSizes);
  ASSERT_EQ(m.faceVertices, r.faceVertices);
  ASSERT_EQ(m.hasUvs(), !r.cornerUvs.empty());
  for (size_t c = 0; c < r.cornerUvs.size(); ++c)
    ASSERT_EQ(m.uvs[m.uvIndices[c]], r.cornerUvs[c]) << "corner " << c;
}

TEST(ObjImport, SmallFilesAsOpenMeshReadsThem) {
  expectSameMesh(
      "# quads and a triangle, texture coordinates per corner, relative and forward indices\r\n"
      "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\nv 2 0 0.25\r\n"
      "vt 0 0\r\nvt 1 0\r\nvt 1 1\r\nvt 0 1 0.5\r\nvt 0.1 0.7\r\n"
      "f -5/-5 -4/-4 -3/-3 -2/-2\r\nf 2/2 5/5 3/3\r\nf 3/6 5/5 6/6\r\nv 3 1 0.5\r\nvt 0.3 0.9\r\n",
      "relative indices, CRLF, vt with w");
  expectSameMesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n", "normals only");
  expectSameMesh(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nvt 0 0\nvt 1 1\n"
      "f 1/1 2/2 3/1\nf 2/2 1/1 4/1\nf 1/1 2/2 5/2\n",
      "a third face on one edge: vertices of its own");
  expectSameMesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 1 2 4\n",
                 "neighbours of opposite orientation");
  expectSameMesh(
      "v 1.0000001 -2.5e-3 3e7\nv 0.1 0.2 0.3 0.9 0.8 0.7\nv -0 1e-30 7\n"
      "f 1 2 3 # a comment\ng group\ns 1\nusemtl none\n",
      "float rounding, colours after positions, trailing comment");
}

// OpenMesh's reader leaves the (u, v) of a corner without a texture coordinate uninitialized (and
// gives every corner one when the file has "vt" lines that no face uses): such files are refused
// by line, or read without (u, v).
TEST(ObjImport, CornersWithAndWithoutTextureCoordinates) {
  try {
    parseControlMesh(
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
        "f 1/1 2/2 3/3\nf 1/1 3/3 4\n",
        "mixed.obj");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "mixed.obj:9:11: f: a face corner without a texture coordinate, where line 8 gives "
              "one: give every corner a texture coordinate (v/vt), or none");
  }
  const ControlMesh unused =
      parseControlMesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.5\nf 1 2 3\n", "unused.obj");
  EXPECT_FALSE(unused.hasUvs());
  EXPECT_EQ(unused.faceVertices, (std::vector<int>{0, 1, 2}));
}

// The OBJ check in chunks (kObjChunkBytes; here down to a line or a byte each) gives the contents
// and counts of the whole file read as one chunk, and the same first problem, its line and column:
// vertices and faces interleaved with relative indices reaching into earlier chunks, comments,
// blank and CRLF lines, and problems in several chunks (the first in the file is reported; a NUL
// byte anywhere before any other).
TEST(ObjImport, ChunksGiveTheContentsAndTheFirstProblemOfTheWholeFile) {
  Rng rng(11);
  std::ostringstream obj;
  obj << "# interleaved\n\n";
  int vertices = 0;
  for (int k = 0; k < 120; ++k) {
    for (int i = 0; i < 3; ++i)
      obj << "v " << rng.uniform() << " " << rng.uniform() << " " << k << (k % 7 ? "\n" : "\r\n")
          << "vt " << rng.uniform() << " " << rng.uniform() << "\n";
    vertices += 3;
    if (k % 5 == 0) obj << "   \n# a comment\ng group" << k << "\n";
    const int a = vertices - 2, b = vertices - 1;
    // The last vertex relative (-1), the others absolute, some from earlier chunks.
    obj << "f " << a << "/" << a << " " << b << "/" << b << " -1/-1";
    if (k > 0) {
      const int older = 1 + static_cast<int>(rng.uniform() * static_cast<float>(vertices - 4));
      obj << " " << older << "/" << older;
    }
    obj << "\n";
  }
  const std::string text = obj.str();
  const MeshTextCounts whole = checkObj(text, "t.obj", text.size() + 1);
  ASSERT_EQ(whole.vertices, 360);
  ASSERT_EQ(whole.faces, 120);
  for (size_t chunk : {size_t{1}, size_t{2}, size_t{7}, size_t{64}, size_t{333}, size_t{4096}}) {
    SCOPED_TRACE(chunk);
    const MeshTextCounts c = checkObj(text, "t.obj", chunk);
    EXPECT_EQ(c.vertices, whole.vertices);
    EXPECT_EQ(c.texcoords, whole.texcoords);
    EXPECT_EQ(c.faces, whole.faces);
    EXPECT_EQ(c.obj.positions, whole.obj.positions);
    EXPECT_EQ(c.obj.texcoords, whole.obj.texcoords);
    EXPECT_EQ(c.obj.faceSizes, whole.obj.faceSizes);
    EXPECT_EQ(c.obj.corners, whole.obj.corners);
    EXPECT_EQ(c.obj.cornerTexcoords, whole.obj.cornerTexcoords);
  }
  const size_t middle = text.find('\n', text.size() / 2) + 1;
  const std::string head = text.substr(0, middle), tail = text.substr(middle);
  const std::string broken[] = {
      text + "f 1/1 2/2 9999/1\n",                         // out of range, in the last chunk
      head + "v 1 2\n" + tail + "f 1 2\n",                 // two problems: the first is reported
      head + "f 1/1 2/2 3\n" + tail,                       // a corner without a texture coordinate
      head + "f 4/4 -1/-1 4/4\n" + tail + "f 1 2\n",       // a vertex twice, then a short face
      head + "v 0 0 x\n" + tail + std::string("\0\n", 2),  // a NUL byte after it wins
      text + "\x7f\x45LF\n",                               // not text
  };
  for (const std::string& t : broken) {
    const auto problem = [&](size_t chunk) {
      try {
        checkObj(t, "t.obj", chunk);
      } catch (const Error& e) {
        return std::string(e.what());
      }
      return std::string("no problem");
    };
    const std::string expected = problem(t.size() + 1);
    ASSERT_EQ(expected.rfind("t.obj:", 0), 0u) << expected;
    std::printf("  %s\n", expected.c_str());
    for (size_t chunk : {size_t{1}, size_t{5}, size_t{100}, size_t{2000}})
      EXPECT_EQ(problem(chunk), expected) << chunk;
  }
}

// A 24 x 24 grid of quads and triangle pairs with random relative indices, with and without
// texture coordinates, and a few faces flipped or repeated (non-manifold).
TEST(ObjImport, ARandomGridAsOpenMeshReadsIt) {
  for (const bool uvs : {true, false}) {
    Rng rng(5);
    std::ostringstream obj;
    const int n = 24;
    for (int y = 0; y <= n; ++y)
      for (int x = 0; x <= n; ++x) {
        obj << "v " << x * 0.37f << " " << y * 0.29f << " " << rng.uniform() << "\n";
        if (uvs) obj << "vt " << x / float(n) << " " << y / float(n) << "\n";
      }
    const int verts = (n + 1) * (n + 1);
    const auto corner = [&](int x, int y) {
      const int v = y * (n + 1) + x + 1;
      std::ostringstream s;
      s << (rng.uniform() < 0.3f ? v - verts - 1 : v);
      if (uvs) s << '/' << v;
      return s.str();
    };
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        std::vector<std::string> c = {corner(x, y), corner(x + 1, y), corner(x + 1, y + 1),
                                      corner(x, y + 1)};
        const float r = rng.uniform();
        if (r < 0.05f) std::swap(c[1], c[3]);  // flipped: opposite orientation to its neighbours
        if (r > 0.5f) {
          obj << "f " << c[0] << " " << c[1] << " " << c[2] << "\nf " << c[0] << " " << c[2] << " "
              << c[3] << "\n";
        } else {
          obj << "f " << c[0] << " " << c[1] << " " << c[2] << " " << c[3] << "\n";
          if (r > 0.47f) obj << "f " << c[0] << " " << c[1] << " " << c[2] << " " << c[3] << "\n";
        }
      }
    expectSameMesh(obj.str(), uvs ? "random grid with (u, v)" : "random grid");
    // Repeated and flipped faces are non-manifold: they got vertices of their own.
    EXPECT_GT(readWithOpenMesh(obj.str()).positions.size(), static_cast<size_t>(verts));
  }
}

}  // namespace
}  // namespace meso
