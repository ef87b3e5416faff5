// Checks OBJ, ASCII OFF and PLY (ASCII and binary) meshes before OpenMesh reads them. OpenMesh
// skips what it cannot use (a face with an index out of range, a NaN vertex) and trusts what it
// reads (an OFF face of -5 vertices makes it allocate 4 GB), so unchecked, a broken file ends in
// "mesh has no faces", in a silently different mesh or in minutes of work. Every problem is
// reported as FILE:LINE:COL: key: what was expected (FILE: element N: ... in a binary body).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace meso {

struct MeshTextCounts {
  long long vertices = 0, faces = 0, texcoords = 0;
  bool checked = false;  // false: a format (binary OFF) left to OpenMesh and checked after it
  // Not empty: the bytes to hand to OpenMesh instead of the file's. A PLY gets its header rewritten
  // in the one layout in which OpenMesh's reader finds where a binary body starts (no comments,
  // one space between words, "\n" line ends); the body is the file's.
  std::string rewritten;
};

// `ext` is ".obj", ".off" or ".ply" (lower case). Throws meso::Error for the first problem found.
MeshTextCounts checkMeshText(std::string_view bytes, const std::filesystem::path& file,
                             const std::string& ext);

// The PLY part of checkMeshText (ply_check.cpp): the header by its grammar, then every element up
// to the faces walked value by value, list lengths against what the file holds and vertex indices
// against the vertex count. OpenMesh's reader trusts a face's vertex count (a count of 10^9 at the
// end of a file loops for minutes) and misreads some well-formed files (a list outside the face's
// vertex indices, an integer x in binary): those are refused by name.
MeshTextCounts checkPly(std::string_view bytes, const std::filesystem::path& file);

}  // namespace meso
