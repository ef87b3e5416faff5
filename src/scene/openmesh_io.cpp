// Control meshes from OBJ, PLY and OFF through OpenMesh. The only file that includes OpenMesh (its
// headers are slow to parse).
#include "meso/scene/mesh_io.h"

#include "meso/core/error.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace meso {
namespace {

using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<>;

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what) {
  throw Error(file.string() + ": " + what);
}

// Face-varying (u, v) from halfedge texture coordinates, identical values shared.
void readUvs(const PolyMesh& mesh, ControlMesh& out) {
  std::map<std::pair<float, float>, int> index;
  for (const auto& f : mesh.faces())
    for (const auto& h : mesh.fh_range(f)) {
      const auto t = mesh.texcoord2D(h);
      const auto key = std::make_pair(t[0], t[1]);
      auto [it, added] = index.emplace(key, static_cast<int>(out.uvs.size()));
      if (added) out.uvs.emplace_back(t[0], t[1]);
      out.uvIndices.push_back(it->second);
    }
}

}  // namespace

ControlMesh loadControlMesh(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) fail(file, "mesh file not found");
  if (!std::filesystem::is_regular_file(file, ec)) fail(file, "not a regular file");
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".obj" && ext != ".ply" && ext != ".off")
    fail(file, "unknown mesh format \"" + ext + "\" (expected .obj, .ply or .off)");
  if (std::filesystem::file_size(file, ec) == 0) fail(file, "empty mesh file");

  PolyMesh mesh;
  mesh.request_halfedge_texcoords2D();
  OpenMesh::IO::Options options = OpenMesh::IO::Options::FaceTexCoord;
  omlog().disable();
  omerr().disable();
  omout().disable();
  const bool ok = OpenMesh::IO::read_mesh(mesh, file.string(), options);
  if (!ok) fail(file, "cannot read mesh (malformed or truncated " + ext.substr(1) + " file?)");
  if (mesh.n_faces() == 0) fail(file, "mesh has no faces");

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
  if (options.check(OpenMesh::IO::Options::FaceTexCoord)) readUvs(mesh, out);
  return out;
}

}  // namespace meso
