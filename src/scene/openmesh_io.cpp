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
#include <limits>
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
// bits with -0 as +0 (as they compare); found with an open-addressing table of the values' bits
// (Fibonacci hashing, linear probing) with twice as many slots as `distinct`, the most values
// there can be (the file's texture coordinates, or its vertices; should more turn up, the table is
// made again with a slot for every corner), in arrays that go back to the system whole (a node per
// value, as a map has, would leave the heap fragmented for the rest of the frame).
void readUvs(const PolyMesh& mesh, bool perVertex, size_t distinct, ControlMesh& out) {
  const auto bitsOf = [](float x) { return std::bit_cast<uint32_t>(x == 0.0f ? 0.0f : x); };
  const size_t corners = mesh.n_halfedges();  // at least the faces' corners
  constexpr uint32_t kEmpty = std::numeric_limits<uint32_t>::max();
  const auto attempt = [&](size_t bound) {
    size_t size = 16;
    int shift = 60;  // the product's top log2(size) bits pick the slot
    while (size < 2 * bound) size *= 2, --shift;
    std::vector<uint64_t> keys(size);
    std::vector<uint32_t> index(size, kEmpty);
    out.uvs.clear();
    out.uvIndices.clear();
    out.uvIndices.reserve(corners / 2);
    for (const auto& f : mesh.faces())
      for (const auto& h : mesh.fh_range(f)) {
        const auto t = perVertex ? mesh.texcoord2D(mesh.to_vertex_handle(h)) : mesh.texcoord2D(h);
        const uint64_t key = uint64_t{bitsOf(t[0])} << 32 | bitsOf(t[1]);
        size_t slot = static_cast<size_t>((key * 0x9e3779b97f4a7c15ull) >> shift);
        while (index[slot] != kEmpty && keys[slot] != key) slot = (slot + 1) & (size - 1);
        if (index[slot] == kEmpty) {
          if (out.uvs.size() >= bound) return false;  // more values than the bound
          keys[slot] = key;
          index[slot] = static_cast<uint32_t>(out.uvs.size());
          out.uvs.emplace_back(t[0], t[1]);
        }
        out.uvIndices.push_back(static_cast<int>(index[slot]));
      }
    return true;
  };
  if (!attempt(std::min(distinct, corners))) attempt(corners);
}

// An OBJ's checked contents into the mesh through OpenMesh's importer, as its OBJ reader hands
// them over: vertices in file order, each face by add_face (which gives a face that would make the
// mesh non-manifold vertices of its own), then the face's texture coordinates on its halfedges
// from the one that ends at its first vertex. Returns whether the faces have texture coordinates
// (the check gives every corner one or none).
bool importObj(const ObjContents& obj, PolyMesh& mesh) {
  OpenMesh::IO::ImporterT<PolyMesh> importer(mesh);
  importer.prepare();
  // Room for all of it (a grid's edges are about its vertices plus its faces): the kernel's arrays
  // do not grow by copies.
  const size_t vertices = obj.positions.size(), faces = obj.faceSizes.size();
  importer.reserve(static_cast<unsigned>(vertices), static_cast<unsigned>(vertices + faces),
                   static_cast<unsigned>(faces));
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
  out.faceSizes.reserve(mesh.n_faces());
  out.faceVertices.reserve(mesh.n_halfedges());  // at least the corners
  for (const auto& f : mesh.faces()) {
    int n = 0;
    for (const auto& v : mesh.fv_range(f)) {
      out.faceVertices.push_back(v.idx());
      ++n;
    }
    out.faceSizes.push_back(n);
  }
  if (options.check(OpenMesh::IO::Options::FaceTexCoord))
    readUvs(mesh, false, static_cast<size_t>(counts.texcoords), out);
  else if (options.check(OpenMesh::IO::Options::VertexTexCoord))
    readUvs(mesh, true, mesh.n_vertices(), out);
  return out;
}

}  // namespace meso
