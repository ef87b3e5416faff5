// Control meshes from OBJ, PLY and OFF through OpenMesh. The only file that includes OpenMesh (its
// headers are slow to parse).
#include "meso/scene/mesh_io.h"

#include "meso/core/error.h"
#include "meso/core/input_file.h"
#include "meso/scene/mesh_text_check.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/ImporterT.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <sstream>
#include <cmath>
#include <utility>
#include <vector>

namespace meso {
namespace {

using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<>;

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what) {
  throw Error(file.string() + ": " + what);
}

// Face-varying (u, v) from halfedge texture coordinates (OBJ) or from the vertices' (PLY, OFF),
// equal values one index, numbered in the order of their first corner. Equal is by the values'
// bits with -0 as +0 (as they compare); found by sorting the corners by value, in arrays that go
// back to the system whole (a node per value, as a map has, would leave the heap fragmented for the
// rest of the frame).
void readUvs(const PolyMesh& mesh, bool perVertex, ControlMesh& out) {
  const auto bitsOf = [](float x) { return std::bit_cast<uint32_t>(x == 0.0f ? 0.0f : x); };
  std::vector<uint64_t> keys;
  std::vector<Vec2> values;
  keys.reserve(mesh.n_halfedges() / 2), values.reserve(mesh.n_halfedges() / 2);
  for (const auto& f : mesh.faces())
    for (const auto& h : mesh.fh_range(f)) {
      const auto t = perVertex ? mesh.texcoord2D(mesh.to_vertex_handle(h)) : mesh.texcoord2D(h);
      keys.push_back(uint64_t{bitsOf(t[0])} << 32 | bitsOf(t[1]));
      values.emplace_back(t[0], t[1]);
    }
  const size_t n = keys.size();
  std::vector<uint32_t> order(n);
  for (size_t c = 0; c < n; ++c) order[c] = static_cast<uint32_t>(c);
  std::sort(order.begin(), order.end(), [&keys](uint32_t a, uint32_t b) {
    return keys[a] != keys[b] ? keys[a] < keys[b] : a < b;
  });
  std::vector<uint32_t> first(n);  // the first corner with the same value
  for (size_t r = 0; r < n; ++r)
    first[order[r]] =
        r > 0 && keys[order[r]] == keys[order[r - 1]] ? first[order[r - 1]] : order[r];
  out.uvIndices.resize(n);
  for (size_t c = 0; c < n; ++c) {
    if (first[c] == c) {
      out.uvIndices[c] = static_cast<int>(out.uvs.size());
      out.uvs.push_back(values[c]);
    } else {
      out.uvIndices[c] = out.uvIndices[first[c]];
    }
  }
}

// OpenMesh's readers trust the element counts: check them against the file size before handing
// it over (PLY files are checked whole by checkPly).
void checkHeader(std::string_view bytes, const std::filesystem::path& file,
                 const std::string& ext) {
  const std::string head(bytes.substr(0, 65536));
  const uintmax_t size = bytes.size();
  if (ext == ".off") {
    std::istringstream words(head);
    std::string magic;
    uint64_t nv = 0, nf = 0;
    if (!(words >> magic) || magic.find("OFF") == std::string::npos)
      fail(file, "not an OFF file (no \"OFF\" magic)");
    if (!(words >> nv >> nf))
      fail(file, "truncated or malformed OFF header (expected vertex and face counts)");
    if (nv * 6 + nf * 8 > size * 2 + 64)
      fail(file, "OFF header declares more vertices or faces than the file holds (truncated?)");
  }
}

// An OBJ's checked contents into the mesh through OpenMesh's importer, as its OBJ reader hands
// them over: vertices in file order, each face by add_face (which gives a face that would make the
// mesh non-manifold vertices of its own), then the face's texture coordinates on its halfedges
// from the one that ends at its first vertex. Returns whether the faces have texture coordinates
// (the check gives every corner one or none).
bool importObj(const ObjContents& obj, PolyMesh& mesh) {
  OpenMesh::IO::ImporterT<PolyMesh> importer(mesh);
  importer.prepare();
  for (const auto& p : obj.positions) importer.add_vertex(OpenMesh::Vec3f(p[0], p[1], p[2]));
  OpenMesh::IO::BaseImporter::VHandles corners;
  std::vector<OpenMesh::Vec2f> texcoords;
  size_t at = 0;
  for (int n : obj.faceSizes) {
    corners.clear();
    texcoords.clear();
    for (int k = 0; k < n; ++k, ++at) {
      corners.emplace_back(obj.corners[at]);
      if (const int t = obj.cornerTexcoords[at]; t >= 0)
        texcoords.emplace_back(obj.texcoords[t][0], obj.texcoords[t][1]);
    }
    const auto face = importer.add_face(corners);
    if (face.is_valid()) importer.add_face_texcoords(face, corners[0], texcoords);
  }
  importer.finish();
  return !obj.texcoords.empty();
}

}  // namespace

ControlMesh loadControlMesh(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (ext != ".obj" && ext != ".ply" && ext != ".off")
    fail(file, "unknown mesh format \"" + ext + "\" (expected .obj, .ply or .off)");
  return parseControlMesh(readInputFile(file, "mesh", kMaxMeshBytes), file);
}

ControlMesh parseControlMesh(std::string_view bytes, const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (ext != ".obj" && ext != ".ply" && ext != ".off")
    fail(file, "unknown mesh format \"" + ext + "\" (expected .obj, .ply or .off)");
  if (bytes.empty()) fail(file, "empty mesh file");
  checkHeader(bytes, file, ext);
  MeshTextCounts counts = checkMeshText(bytes, file, ext);

  PolyMesh mesh;
  mesh.request_halfedge_texcoords2D();
  OpenMesh::IO::Options options = OpenMesh::IO::Options::FaceTexCoord;
  // PLY and OFF carry uv per vertex. Not asked of OBJ: its reader then writes a vertex uv through
  // the handle of a face it rejected (out of bounds).
  if (ext != ".obj") {
    mesh.request_vertex_texcoords2D();
    options += OpenMesh::IO::Options::VertexTexCoord;
  }
  omlog().disable();
  omerr().disable();
  omout().disable();
  // Some OpenMesh readers write to std::cerr directly: keep their chatter out of meso's output.
  std::streambuf* cerrBuffer = std::cerr.rdbuf(nullptr);
  bool ok = false;
  try {
    if (ext == ".obj") {
      ok = true;
      if (!importObj(counts.obj, mesh)) options -= OpenMesh::IO::Options::FaceTexCoord;
      counts.obj = {};  // its arrays go back before the mesh is converted
    } else {
      // Moved, not copied: a mesh file may be gigabytes.
      std::istringstream stream{counts.rewritten.empty() ? std::string(bytes)
                                                         : std::move(counts.rewritten)};
      ok = OpenMesh::IO::read_mesh(mesh, stream, ext, options);
    }
  } catch (...) {
    ok = false;
  }
  std::cerr.rdbuf(cerrBuffer);
  if (!ok) fail(file, "cannot read mesh (malformed or truncated " + ext.substr(1) + " file?)");
  if (mesh.n_faces() == 0)
    fail(file, counts.checked
                   ? "mesh has no faces: the reader rejected all " + std::to_string(counts.faces) +
                         " (non-manifold: an edge shared by more than two faces, or neighbours of "
                         "opposite orientation)"
                   : "mesh has no faces");

  ControlMesh out;
  out.positions.reserve(mesh.n_vertices());
  for (const auto& v : mesh.vertices()) {
    const auto p = mesh.point(v);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      fail(file, "vertex " + std::to_string(v.idx() + 1) + " has a NaN or infinite coordinate");
    out.positions.emplace_back(p[0], p[1], p[2]);
  }
  for (const auto& f : mesh.faces()) {
    int n = 0;
    for (const auto& v : mesh.fv_range(f)) {
      out.faceVertices.push_back(v.idx());
      ++n;
    }
    out.faceSizes.push_back(n);
  }
  if (options.check(OpenMesh::IO::Options::FaceTexCoord))
    readUvs(mesh, false, out);
  else if (options.check(OpenMesh::IO::Options::VertexTexCoord))
    readUvs(mesh, true, out);
  return out;
}

}  // namespace meso
