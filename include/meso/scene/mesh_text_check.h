// Checks OBJ, ASCII OFF and PLY (ASCII and binary) meshes before OpenMesh reads them. OpenMesh
// skips what it cannot use (a face with an index out of range, a NaN vertex) and trusts what it
// reads (an OFF face of -5 vertices makes it allocate 4 GB), so unchecked, a broken file ends in
// "mesh has no faces", in a silently different mesh or in minutes of work. Every problem is
// reported as FILE:LINE:COL: key: what was expected (FILE: element N: ... in a binary body). An
// OBJ's check also keeps what it parsed (ObjContents), which goes to OpenMesh's importer in place
// of OpenMesh's own OBJ reader.
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace meso {

// What an OBJ file holds, as its checked text says (OpenMesh's OBJ reader parses the same text
// through iostreams, about 5 times as long): the positions of its "v" lines, the (u, v) of its
// "vt" lines, and per "f" line its vertex count, then per corner its 0-based vertex index and
// texture coordinate index (-1: none), relative indices resolved.
struct ObjContents {
  std::vector<std::array<float, 3>> positions;
  std::vector<std::array<float, 2>> texcoords;
  std::vector<int> faceSizes, corners, cornerTexcoords;
};

struct MeshTextCounts {
  long long vertices = 0, faces = 0, texcoords = 0;
  bool checked = false;  // false: not an .obj, .off or .ply file (checkMeshText reads none)
  // Not empty: the bytes to hand to OpenMesh instead of the file's. A PLY gets its header rewritten
  // in the one layout in which OpenMesh's reader finds where a binary body starts (no comments,
  // one space between words, "\n" line ends); the body is the file's. An ASCII OFF is rewritten
  // whole, as checked: no comments, the counts on a line of their own, a face's size and indices
  // alone on its line.
  std::string rewritten;
  ObjContents obj;  // an OBJ's contents (empty for the other formats)
};

// `ext` is ".obj", ".off" or ".ply" (lower case). Throws meso::Error for the first problem found.
MeshTextCounts checkMeshText(std::string_view bytes, const std::filesystem::path& file,
                             const std::string& ext);

// The OBJ part of checkMeshText: the file in chunks of about `chunkBytes` (whole lines), counted
// and then checked into the contents' arrays on every core. The contents and the first problem in
// file order (its message, line and column) are those of one chunk, whatever the chunk size.
inline constexpr size_t kObjChunkBytes = size_t{1} << 20;
MeshTextCounts checkObj(std::string_view bytes, const std::filesystem::path& file,
                        size_t chunkBytes = kObjChunkBytes);

// The PLY part of checkMeshText (ply_check.cpp): the header by its grammar, then every element up
// to the faces walked value by value, list lengths against what the file holds and vertex indices
// against the vertex count. OpenMesh's reader trusts a face's vertex count (a count of 10^9 at the
// end of a file loops for minutes) and misreads some well-formed files (a list outside the face's
// vertex indices, an integer x in binary): those are refused by name.
MeshTextCounts checkPly(std::string_view bytes, const std::filesystem::path& file);

}  // namespace meso
