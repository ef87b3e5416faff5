#include "meso/scene/mesh_text_check.h"

#include "meso/core/error.h"
#include "meso/core/huge_pages.h"
#include "mesh_text_tokens.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <exception>
#include <set>
#include <string>
#include <vector>

namespace meso {
namespace {

using namespace mesh_text;

// Index `raw` (1-based, or negative: relative to the `defined` so far) into [1, total].
long long objIndex(const LineReader& r, const Token& t, std::string_view text, long long defined,
                   long long total, const char* what) {
  const std::string key = "f";
  const long long raw = integer(r, t, text, key);
  if (raw == 0)
    r.fail(t.column, key,
           std::string("expected a ") + what + " index of 1 or more (OBJ counts from 1), got 0");
  const long long index = raw > 0 ? raw : defined + raw + 1;
  if (index < 1 || index > total)
    r.fail(t.column, key,
           std::string(what) + " index " + std::to_string(raw) + " out of range: the file has " +
               std::to_string(raw > 0 ? total : defined) + " " +
               (std::string_view(what) == "vertex" ? std::string("vertices")
                                                   : what + std::string("s")) +
               (raw > 0 ? "" : " before this face"));
  return index;
}

// A number as float, rounded once from its text as OpenMesh's `stream >> float` rounds it, and
// checked as number() checks it (which a finite float read from the whole token passes; the
// others are read again as a double there, for the error or a value under float's range).
float single(const LineReader& r, const Token& t, std::string_view key) {
  float v = 0.0f;
  const char* end = t.text.data() + t.text.size();
  const auto [ptr, ec] = std::from_chars(t.text.data(), end, v);
  if (ec == std::errc() && ptr == end && std::isfinite(v)) return v;
  const double checked = number(r, t, std::string(key));
  return ec == std::errc() ? v : static_cast<float>(checked);  // (under- or overflow)
}

const std::set<std::string_view>& knownObjKeys() {
  static const std::set<std::string_view> kKnown = {
      "vn",       "vp",     "o",          "g",         "s",     "l",     "p",     "usemtl",
      "mtllib",   "cstype", "deg",        "curv",      "curv2", "surf",  "parm",  "end",
      "trim",     "hole",   "scrv",       "sp",        "con",   "mg",    "bevel", "c_interp",
      "d_interp", "lod",    "shadow_obj", "trace_obj", "ctech", "stech", "bmat",  "step",
      "call",     "csh",    "maplib",     "usemap"};
  return kKnown;
}

// One chunk of an OBJ's lines (whole lines), checked on its own thread: its counts first, then its
// statements into its share of the contents' arrays.
struct ObjChunk {
  std::string_view bytes;
  int firstLine = 0;  // lines before it
  long long vertices = 0, texcoords = 0;
  size_t faces = 0, corners = 0;
  // Where its statements go in the contents (the counts of the chunks before it).
  long long vertexBase = 0, texcoordBase = 0;
  size_t faceBase = 0, cornerBase = 0;
  // The first corner with a texture coordinate and the first without: a file must give every
  // corner one or none (OpenMesh leaves the (u, v) of a corner without one uninitialized).
  FileLoc withUv, withoutUv;
  std::exception_ptr error;  // its first problem
};

// Chunks of about `chunkBytes`, each ending after a line end (the last at the end of the file).
std::vector<ObjChunk> objChunks(std::string_view bytes, size_t chunkBytes) {
  std::vector<ObjChunk> chunks;
  size_t start = 0;
  while (start < bytes.size() || chunks.empty()) {
    size_t end = bytes.size();
    if (bytes.size() - start > chunkBytes) {
      const size_t newline = bytes.find('\n', start + chunkBytes);
      if (newline != std::string_view::npos) end = newline + 1;
    }
    ObjChunk c;
    c.bytes = bytes.substr(start, end - start);
    chunks.push_back(c);
    start = end;
  }
  return chunks;
}

// Counts the statements of a chunk (a NUL byte is its only problem here).
void countObjChunk(ObjChunk& c, const std::filesystem::path& file) {
  LineReader r(c.bytes, file, c.firstLine);
  std::vector<Token> t;
  while (r.next(t)) {
    if (t[0].text == "v") ++c.vertices;
    if (t[0].text == "vt") ++c.texcoords;
    if (t[0].text == "f") ++c.faces, c.corners += t.size() - 1;
  }
}

// Checks the statements of a chunk into its share of the contents' arrays (sized for every
// chunk); vertexTotal and texcoordTotal are the file's counts.
void parseObjChunk(ObjChunk& c, const std::filesystem::path& file, long long vertexTotal,
                   long long texcoordTotal, ObjContents& obj) {
  LineReader r(c.bytes, file, c.firstLine);
  std::vector<Token> t;
  long long v = c.vertexBase, vt = c.texcoordBase;  // defined so far
  size_t face = c.faceBase, corner = c.cornerBase;
  const std::set<std::string_view>& known = knownObjKeys();
  while (r.next(t)) {
    const std::string_view key = t[0].text;
    if (key == "v") {
      if (t.size() < 4)
        r.fail(t[0].column, "v",
               "expected x y z, got " + std::to_string(t.size() - 1) + " numbers");
      std::array<float, 3> p{};
      for (size_t i = 1; i < t.size() && i <= 4; ++i) {
        const float x = single(r, t[i], "v");
        if (i <= 3) p[i - 1] = x;
      }
      obj.positions[static_cast<size_t>(v++)] = p;
    } else if (key == "vt") {
      if (t.size() < 3)
        r.fail(t[0].column, "vt",
               "expected u v [w], got " + std::to_string(t.size() - 1) +
                   (t.size() == 2 ? " number" : " numbers"));
      std::array<float, 2> uv{};
      for (size_t i = 1; i < t.size() && i <= 3; ++i) {
        const float x = single(r, t[i], "vt");
        if (i <= 2) uv[i - 1] = x;
      }
      obj.texcoords[static_cast<size_t>(vt++)] = uv;
    } else if (key == "f") {
      if (t.size() < 4)
        r.fail(t[0].column, "f",
               "expected a face of at least 3 vertices, got " + std::to_string(t.size() - 1));
      std::set<long long> seen;  // large faces only; small ones scan their corners
      const auto first = obj.corners.begin() + static_cast<std::ptrdiff_t>(corner);
      for (size_t i = 1; i < t.size(); ++i) {
        const std::string_view text = t[i].text;
        const size_t s1 = text.find('/');
        const long long vi = objIndex(r, t[i], text.substr(0, s1), v, vertexTotal, "vertex");
        const auto end = obj.corners.begin() + static_cast<std::ptrdiff_t>(corner);
        const bool twice = t.size() > 33 ? !seen.insert(vi).second
                                         : std::find(first, end, static_cast<int>(vi - 1)) != end;
        if (twice)
          r.fail(t[i].column, "f", "vertex " + std::to_string(vi) + " appears twice in the face");
        obj.corners[corner] = static_cast<int>(vi - 1);
        obj.cornerTexcoords[corner] = -1;
        const std::string_view rest =
            s1 == std::string_view::npos ? std::string_view() : text.substr(s1 + 1);
        const std::string_view tex = rest.substr(0, rest.find('/'));
        FileLoc& firstOfKind = tex.empty() ? c.withoutUv : c.withUv;
        if (firstOfKind.line == 0) firstOfKind = {file.string(), r.line(), t[i].column};
        if (!tex.empty())
          obj.cornerTexcoords[corner] =
              static_cast<int>(objIndex(r, t[i], tex, vt, texcoordTotal, "texture coordinate") - 1);
        ++corner;
      }
      obj.faceSizes[face++] = static_cast<int>(t.size() - 1);
    } else if (!known.count(key)) {
      if (!printable(key))
        r.fail(
            t[0].column, "",
            "unexpected bytes " + shown(key) + " (not an OBJ statement: corrupt or binary file?)");
    }
  }
}

// Runs `step` on every chunk in parallel and throws the first problem in file order.
template <class Step>
void eachObjChunk(std::vector<ObjChunk>& chunks, Step&& step) {
  tbb::parallel_for(size_t{0}, chunks.size(), [&](size_t i) {
    try {
      step(chunks[i]);
    } catch (...) {
      chunks[i].error = std::current_exception();
    }
  });
  for (const ObjChunk& c : chunks)
    if (c.error) std::rethrow_exception(c.error);
}

}  // namespace

MeshTextCounts checkObj(std::string_view bytes, const std::filesystem::path& file,
                        size_t chunkBytes) {
  MeshTextCounts counts;
  ObjContents& obj = counts.obj;
  counts.checked = true;
  // Totals first (faces may refer to vertices that come later), chunk by chunk; a chunk's first
  // line follows the line ends before it.
  std::vector<ObjChunk> chunks = objChunks(bytes, std::max<size_t>(chunkBytes, 1));
  std::vector<int> lineEnds(chunks.size());
  tbb::parallel_for(size_t{0}, chunks.size(), [&](size_t i) {
    lineEnds[i] =
        static_cast<int>(std::count(chunks[i].bytes.begin(), chunks[i].bytes.end(), '\n'));
  });
  for (size_t i = 1; i < chunks.size(); ++i)
    chunks[i].firstLine = chunks[i - 1].firstLine + lineEnds[i - 1];
  eachObjChunk(chunks, [&](ObjChunk& c) { countObjChunk(c, file); });
  size_t faces = 0, corners = 0;
  for (ObjChunk& c : chunks) {
    c.vertexBase = counts.vertices;
    c.texcoordBase = counts.texcoords;
    c.faceBase = faces;
    c.cornerBase = corners;
    counts.vertices += c.vertices;
    counts.texcoords += c.texcoords;
    faces += c.faces;
    corners += c.corners;
  }
  // Made to size, their pages mapped on every core: each chunk fills its share.
  resizePopulated(obj.positions, static_cast<size_t>(counts.vertices));
  resizePopulated(obj.texcoords, static_cast<size_t>(counts.texcoords));
  resizePopulated(obj.faceSizes, faces);
  resizePopulated(obj.corners, corners);
  resizePopulated(obj.cornerTexcoords, corners);
  eachObjChunk(
      chunks, [&](ObjChunk& c) { parseObjChunk(c, file, counts.vertices, counts.texcoords, obj); });
  counts.faces = static_cast<long long>(faces);
  FileLoc withUv, withoutUv;
  for (const ObjChunk& c : chunks) {
    if (withUv.line == 0) withUv = c.withUv;
    if (withoutUv.line == 0) withoutUv = c.withoutUv;
  }
  if (counts.faces == 0)
    throw Error(file.string() + ": mesh has no faces (" + std::to_string(counts.vertices) +
                " vertices and no \"f\" line)");
  if (withUv.line > 0 && withoutUv.line > 0)
    throw Error(withoutUv, "f",
                "a face corner without a texture coordinate, where line " +
                    std::to_string(withUv.line) +
                    " gives one: give every corner a texture coordinate (v/vt), or none");
  if (withUv.line == 0) obj.texcoords.clear();  // "vt" lines that no face uses: no (u, v)
  return counts;
}

namespace {

MeshTextCounts checkOff(std::string_view bytes, const std::filesystem::path& file) {
  MeshTextCounts counts;
  LineReader r(bytes, file);
  std::vector<Token> t;
  if (!r.next(t)) throw Error(file.string() + ": empty OFF file");
  // [ST][C][N][4][n]OFF [BINARY]: texture coordinates, colours, normals, homogeneous,
  // n-dimensional.
  std::string_view magic = t[0].text;
  bool normals = false;  // N: a normal after each vertex's coordinates
  for (std::string_view prefix : {"ST", "C", "N"})
    if (magic.substr(0, prefix.size()) == prefix) {
      magic.remove_prefix(prefix.size());
      normals = normals || prefix == "N";
    }
  const bool homogeneous = magic.substr(0, 1) == "4";
  if (homogeneous) magic.remove_prefix(1);
  if (magic.substr(0, 1) == "n")
    r.fail(t[0].column, "", "n-dimensional OFF (nOFF) is not supported");
  if (magic != "OFF")
    r.fail(t[0].column, "",
           "not an OFF file (expected [ST][C][N][4]OFF, got " + shown(t[0].text) + ")");
  if (t.size() > 1 && t[1].text == "BINARY")
    r.fail(t[1].column, "", "binary OFF is not supported (convert it to ASCII OFF, OBJ or PLY)");
  // What OpenMesh reads of a vertex line before it takes the rest of the line (colours, uv).
  const size_t coordinates = (homogeneous ? 4 : 3) + (normals ? 3 : 0);
  std::vector<Token> header(t.begin() + 1, t.end());
  if (header.empty() && !r.next(header))
    r.fail(1, "", "truncated OFF: expected the vertex, face and edge counts");
  if (header.size() < 2) r.fail(header[0].column, "", "expected the vertex, face and edge counts");
  const long long nv = integer(r, header[0], header[0].text, "vertex count");
  const long long nf = integer(r, header[1], header[1].text, "face count");
  if (nv < 0 || nf < 0) r.fail(header[0].column, "", "expected counts of 0 or more");
  if (nf == 0) throw Error(file.string() + ": mesh has no faces (the OFF header declares 0)");
  counts.checked = true;
  // OpenMesh reads the file as one stream of numbers after its first line, which it skips whole: a
  // count on that line, a comment or a number after a face's indices (a face colour, which it does
  // not skip even under COFF) would be read as the next count, and a large one made it loop over
  // billions of indices. It gets the file as checked instead: the magic word, the counts, then each
  // vertex's line and each face's size and indices, a line each.
  std::string& out = counts.rewritten;
  out.reserve(bytes.size() + 16);
  out.append(t[0].text).append("\n");
  const auto append = [&](auto first, auto last) {
    for (auto it = first; it != last; ++it)
      out.append(it->text).append(it + 1 == last ? "\n" : " ");
  };
  out.append(header[0].text).append(" ").append(header[1].text).append(" 0\n");
  const auto truncated = [&](const char* what, int line) {
    throw Error(file.string() + ": truncated OFF: the header declares " + std::to_string(nv) +
                " vertices and " + std::to_string(nf) + " faces; the file ends after " +
                std::to_string(counts.vertices) + " vertices and " + std::to_string(counts.faces) +
                " faces (expected " + what + " at line " + std::to_string(line) + ")");
  };
  for (; counts.vertices < nv; ++counts.vertices) {
    if (!r.next(t)) truncated("a vertex", r.line() + 1);
    if (t.size() < coordinates && r.atEnd()) truncated("a vertex", r.line());
    if (t.size() < coordinates)
      r.fail(t[0].column, "vertex " + std::to_string(counts.vertices),
             std::string(homogeneous ? "expected x y z w" : "expected x y z") +
                 (normals ? " nx ny nz" : "") + ", got " + std::to_string(t.size()) + " numbers");
    for (size_t i = 0; i < coordinates; ++i)
      number(r, t[i], "vertex " + std::to_string(counts.vertices));
    append(t.begin(), t.end());
  }
  for (; counts.faces < nf; ++counts.faces) {
    if (!r.next(t)) truncated("a face", r.line() + 1);
    const std::string key = "face " + std::to_string(counts.faces);
    const long long n = integer(r, t[0], t[0].text, key);
    if (n < 3)
      r.fail(t[0].column, key, "expected a face size of 3 or more, got " + std::to_string(n));
    if (static_cast<long long>(t.size()) - 1 < n && r.atEnd()) truncated("a whole face", r.line());
    if (static_cast<long long>(t.size()) - 1 < n)
      r.fail(t[0].column, key,
             "face size " + std::to_string(n) + " but " + std::to_string(t.size() - 1) +
                 " indices on the line");
    std::set<long long> seen;
    for (long long i = 1; i <= n; ++i) {
      const long long vi = integer(r, t[i], t[i].text, key);
      if (vi < 0 || vi >= nv)
        r.fail(t[i].column, key,
               "vertex index " + std::to_string(vi) + " out of range [0, " + std::to_string(nv) +
                   ") (OFF counts from 0)");
      if (!seen.insert(vi).second)
        r.fail(t[i].column, key, "vertex " + std::to_string(vi) + " appears twice in the face");
    }
    // The face's size and indices alone: what follows them (a colour) is not read.
    append(t.begin(), t.begin() + n + 1);
  }
  return counts;
}

}  // namespace

MeshTextCounts checkMeshText(std::string_view bytes, const std::filesystem::path& file,
                             const std::string& ext) {
  if (ext == ".obj") return checkObj(bytes, file, kObjChunkBytes);
  if (ext == ".off") return checkOff(bytes, file);
  if (ext == ".ply") return checkPly(bytes, file);
  return {};
}

}  // namespace meso
