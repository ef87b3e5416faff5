#include "meso/scene/mesh_text_check.h"

#include "meso/core/error.h"

#include <algorithm>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <set>
#include <string>
#include <vector>

namespace meso {
namespace {

struct Token {
  std::string_view text;
  int column;  // 1-based
};

// The whitespace-separated tokens of a line, up to a '#' comment.
std::vector<Token> tokenize(std::string_view line) {
  std::vector<Token> tokens;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    if (i >= line.size() || line[i] == '#') break;
    const size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    tokens.push_back({line.substr(start, i - start), static_cast<int>(start) + 1});
  }
  return tokens;
}

std::string shown(std::string_view t) {
  std::string s(t.substr(0, 40));
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
  return "\"" + s + (t.size() > 40 ? "...\"" : "\"");
}

bool printable(std::string_view t) {
  for (char c : t)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) return false;
  return true;
}

class LineReader {
 public:
  LineReader(std::string_view bytes, const std::filesystem::path& file)
      : bytes_(bytes), file_(file.string()) {}
  // The next line's tokens (empty lines and comments skipped); false at the end.
  bool next(std::vector<Token>& tokens) {
    while (!done_) {
      size_t end = bytes_.find('\n', at_);
      if (end == std::string_view::npos) end = bytes_.size();
      const std::string_view line = bytes_.substr(at_, end - at_);
      if (end >= bytes_.size()) done_ = true;
      at_ = end + 1;
      ++line_;
      if (line.find('\0') != std::string_view::npos)
        fail(1, "", "unexpected binary data (a NUL byte) in a text mesh file");
      tokens = tokenize(line);
      if (!tokens.empty()) return true;
    }
    return false;
  }
  [[noreturn]] void fail(int column, const std::string& key, const std::string& what) const {
    throw Error(FileLoc{file_, line_, column}, key, what);
  }
  int line() const { return line_; }
  bool atEnd() const { return done_; }

 private:
  std::string_view bytes_;
  std::string file_;
  size_t at_ = 0;
  int line_ = 0;
  bool done_ = false;
};

double number(const LineReader& r, const Token& t, const std::string& key) {
  double v = 0.0;
  const char* end = t.text.data() + t.text.size();
  const auto [ptr, ec] = std::from_chars(t.text.data(), end, v);
  if (ptr != end || (ec != std::errc() && ec != std::errc::result_out_of_range))
    r.fail(t.column, key, "expected a number, got " + shown(t.text));
  if (ec == std::errc::result_out_of_range || !std::isfinite(v) || std::abs(v) > FLT_MAX)
    r.fail(t.column, key, "expected a finite single-precision number, got " + shown(t.text));
  return v;
}

long long integer(const LineReader& r, const Token& t, std::string_view text,
                  const std::string& key) {
  long long v = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ptr != end || ec != std::errc())
    r.fail(t.column, key, "expected an integer index, got " + shown(text));
  return v;
}

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

MeshTextCounts checkObj(std::string_view bytes, const std::filesystem::path& file) {
  MeshTextCounts counts;
  counts.checked = true;
  {  // Totals first: faces may refer to vertices that come later.
    LineReader r(bytes, file);
    std::vector<Token> t;
    while (r.next(t)) {
      if (t[0].text == "v") ++counts.vertices;
      if (t[0].text == "vt") ++counts.texcoords;
    }
  }
  static const std::set<std::string_view> kKnown = {
      "vn",       "vp",     "o",          "g",         "s",     "l",     "p",     "usemtl",
      "mtllib",   "cstype", "deg",        "curv",      "curv2", "surf",  "parm",  "end",
      "trim",     "hole",   "scrv",       "sp",        "con",   "mg",    "bevel", "c_interp",
      "d_interp", "lod",    "shadow_obj", "trace_obj", "ctech", "stech", "bmat",  "step",
      "call",     "csh",    "maplib",     "usemap"};
  LineReader r(bytes, file);
  std::vector<Token> t;
  long long v = 0, vt = 0;
  while (r.next(t)) {
    const std::string_view key = t[0].text;
    if (key == "v") {
      if (t.size() < 4)
        r.fail(t[0].column, "v",
               "expected x y z, got " + std::to_string(t.size() - 1) + " numbers");
      for (size_t i = 1; i < t.size() && i <= 4; ++i) number(r, t[i], "v");
      ++v;
    } else if (key == "vt") {
      if (t.size() < 2) r.fail(t[0].column, "vt", "expected u [v [w]]");
      for (size_t i = 1; i < t.size() && i <= 3; ++i) number(r, t[i], "vt");
      ++vt;
    } else if (key == "f") {
      if (t.size() < 4)
        r.fail(t[0].column, "f",
               "expected a face of at least 3 vertices, got " + std::to_string(t.size() - 1));
      std::set<long long> seen;
      for (size_t i = 1; i < t.size(); ++i) {
        const std::string_view c = t[i].text;
        const size_t s1 = c.find('/');
        const long long vi = objIndex(r, t[i], c.substr(0, s1), v, counts.vertices, "vertex");
        if (!seen.insert(vi).second)
          r.fail(t[i].column, "f", "vertex " + std::to_string(vi) + " appears twice in the face");
        if (s1 == std::string_view::npos) continue;
        const std::string_view rest = c.substr(s1 + 1);
        const std::string_view tex = rest.substr(0, rest.find('/'));
        if (!tex.empty()) objIndex(r, t[i], tex, vt, counts.texcoords, "texture coordinate");
      }
      ++counts.faces;
    } else if (!kKnown.count(key)) {
      if (!printable(key))
        r.fail(
            t[0].column, "",
            "unexpected bytes " + shown(key) + " (not an OBJ statement: corrupt or binary file?)");
    }
  }
  if (counts.faces == 0)
    throw Error(file.string() + ": mesh has no faces (" + std::to_string(counts.vertices) +
                " vertices and no \"f\" line)");
  return counts;
}

MeshTextCounts checkOff(std::string_view bytes, const std::filesystem::path& file) {
  MeshTextCounts counts;
  LineReader r(bytes, file);
  std::vector<Token> t;
  if (!r.next(t)) throw Error(file.string() + ": empty OFF file");
  // [ST][C][N][4][n]OFF [BINARY]: texture coordinates, colours, normals, homogeneous,
  // n-dimensional.
  std::string_view magic = t[0].text;
  for (std::string_view prefix : {"ST", "C", "N"})
    if (magic.substr(0, prefix.size()) == prefix) magic.remove_prefix(prefix.size());
  const bool homogeneous = magic.substr(0, 1) == "4";
  if (homogeneous) magic.remove_prefix(1);
  if (magic.substr(0, 1) == "n")
    r.fail(t[0].column, "", "n-dimensional OFF (nOFF) is not supported");
  if (magic != "OFF")
    r.fail(t[0].column, "",
           "not an OFF file (expected [ST][C][N][4]OFF, got " + shown(t[0].text) + ")");
  if (t.size() > 1 && t[1].text == "BINARY")
    r.fail(t[1].column, "", "binary OFF is not supported (convert it to ASCII OFF, OBJ or PLY)");
  const size_t coordinates = homogeneous ? 4 : 3;
  std::vector<Token> header(t.begin() + 1, t.end());
  if (header.empty() && !r.next(header))
    r.fail(1, "", "truncated OFF: expected the vertex, face and edge counts");
  if (header.size() < 2) r.fail(header[0].column, "", "expected the vertex, face and edge counts");
  const long long nv = integer(r, header[0], header[0].text, "vertex count");
  const long long nf = integer(r, header[1], header[1].text, "face count");
  if (nv < 0 || nf < 0) r.fail(header[0].column, "", "expected counts of 0 or more");
  if (nf == 0) throw Error(file.string() + ": mesh has no faces (the OFF header declares 0)");
  counts.checked = true;
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
             std::string(homogeneous ? "expected x y z w" : "expected x y z") + ", got " +
                 std::to_string(t.size()) + " numbers");
    for (size_t i = 0; i < coordinates; ++i)
      number(r, t[i], "vertex " + std::to_string(counts.vertices));
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
  }
  return counts;
}

// OpenMesh's PLY reader loops forever on some malformed headers (a property before any element, an
// unknown type): the header must follow the grammar exactly before it is handed over.
void checkPlyHeader(std::string_view bytes, const std::filesystem::path& file) {
  static const std::set<std::string_view> kTypes = {
      "char", "uchar", "short", "ushort", "int",   "uint",   "float",   "double",
      "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"};
  LineReader r(bytes.substr(0, std::min<size_t>(bytes.size(), 65536)), file);
  std::vector<Token> t;
  if (!r.next(t) || t.size() != 1 || t[0].text != "ply")
    r.fail(1, "", "not a PLY file (expected \"ply\" alone on line 1)");
  bool format = false, element = false, vertex = false, face = false;
  std::string_view current;
  std::set<std::string_view> vertexProperties;
  while (r.next(t)) {
    const std::string_view key = t[0].text;
    if (key == "end_header") {
      if (!format) r.fail(1, "", "PLY header without a format line");
      if (!vertex || !vertexProperties.count("x") || !vertexProperties.count("y") ||
          !vertexProperties.count("z"))
        r.fail(1, "", "PLY header without an element vertex with properties x, y and z");
      if (!face)
        r.fail(1, "", "PLY header without an element face with a list property vertex_indices");
      return;
    }
    if (key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      if (t.size() != 3 ||
          (t[1].text != "ascii" && t[1].text != "binary_little_endian" &&
           t[1].text != "binary_big_endian") ||
          t[2].text != "1.0")
        r.fail(t[0].column, "format",
               "expected ascii, binary_little_endian or binary_big_endian and version 1.0");
      format = true;
    } else if (key == "element") {
      if (t.size() != 3) r.fail(t[0].column, "element", "expected a name and a count");
      if (integer(r, t[2], t[2].text, "element") < 0)
        r.fail(t[2].column, "element", "expected a count of 0 or more");
      element = true;
      current = t[1].text;
      vertex = vertex || current == "vertex";
    } else if (key == "property") {
      if (!element) r.fail(t[0].column, "property", "a property before any element");
      const bool list = t.size() >= 2 && t[1].text == "list";
      if (t.size() != (list ? 5u : 3u))
        r.fail(t[0].column, "property", "expected TYPE NAME or list TYPE TYPE NAME");
      for (size_t i = list ? 2 : 1; i + 1 < t.size(); ++i)
        if (!kTypes.count(t[i].text))
          r.fail(t[i].column, "property", "unknown type " + shown(t[i].text));
      if (current == "vertex") vertexProperties.insert(t.back().text);
      if (current == "face" && list &&
          (t.back().text == "vertex_indices" || t.back().text == "vertex_index"))
        face = true;
    } else {
      r.fail(t[0].column, "", "unexpected " + shown(key) + " in the PLY header");
    }
  }
  r.fail(1, "", "truncated or malformed PLY header (no end_header)");
}

}  // namespace

MeshTextCounts checkMeshText(std::string_view bytes, const std::filesystem::path& file,
                             const std::string& ext) {
  if (ext == ".obj") return checkObj(bytes, file);
  if (ext == ".off") return checkOff(bytes, file);
  if (ext == ".ply") checkPlyHeader(bytes, file);
  return {};
}

}  // namespace meso
