// PLY meshes checked before OpenMesh reads them: the header by its grammar, the body value by
// value (include/meso/scene/mesh_text_check.h says why).
#include "meso/core/error.h"
#include "meso/scene/mesh_text_check.h"
#include "mesh_text_tokens.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace meso {
namespace {

using namespace mesh_text;

struct PlyProperty {
  std::string name, type;
  std::string countType;  // not empty: a list of `type` values preceded by a count of this type
};

struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  std::string format;
  std::vector<PlyElement> elements;
  size_t bodyOffset = 0;  // the first byte after the end_header line
  int bodyLine = 0;       // the line it starts
};

// Bytes per value of each scalar type.
const std::map<std::string_view, int>& typeSizes() {
  static const std::map<std::string_view, int> kSizes = {
      {"char", 1},  {"uchar", 1},   {"int8", 1},   {"uint8", 1},  {"short", 2}, {"ushort", 2},
      {"int16", 2}, {"uint16", 2},  {"int", 4},    {"uint", 4},   {"int32", 4}, {"uint32", 4},
      {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
  return kSizes;
}

bool isFloat(std::string_view type) {
  return type == "float" || type == "float32" || type == "double" || type == "float64";
}

bool isSigned(std::string_view type) {
  return type == "char" || type == "int8" || type == "short" || type == "int16" || type == "int" ||
         type == "int32";
}

// The vertex properties OpenMesh reads as floats: in a binary body it skips no bytes for them when
// they have an integer type, and everything after is misread.
bool readAsFloat(std::string_view element, std::string_view name) {
  static const std::set<std::string_view> kNames = {"x",  "y", "z", "nx", "ny",
                                                    "nz", "u", "v", "s",  "t"};
  return element == "vertex" && kNames.count(name);
}

bool isVertexIndices(const PlyElement& e, const PlyProperty& p) {
  return e.name == "face" && !p.countType.empty() &&
         (p.name == "vertex_indices" || p.name == "vertex_index");
}

// OpenMesh's PLY reader loops forever on some malformed headers (a property before any element, an
// unknown type): the header must follow the grammar exactly before it is handed over.
PlyHeader readHeader(std::string_view bytes, const std::filesystem::path& file) {
  LineReader r(bytes.substr(0, std::min<size_t>(bytes.size(), 65536)), file);
  std::vector<Token> t;
  if (!r.next(t) || t.size() != 1 || t[0].text != "ply")
    r.fail(1, "", "not a PLY file (expected \"ply\" alone on line 1)");
  PlyHeader h;
  while (r.next(t)) {
    const std::string_view key = t[0].text;
    if (key == "end_header") {
      if (t.size() != 1) r.fail(t[1].column, "end_header", "expected nothing after end_header");
      if (h.format.empty()) r.fail(1, "", "PLY header without a format line");
      // A header whose end_header line ends the file has an empty body (not one past the end).
      h.bodyOffset = std::min(r.offset(), bytes.size());
      h.bodyLine = r.line() + 1;
      const PlyElement* vertex = nullptr;
      for (const PlyElement& e : h.elements) {
        if (e.name == "vertex") vertex = &e;
        if (e.name != "face") continue;
        if (!vertex) r.fail(1, "", "PLY header declares element face before element vertex");
        for (const PlyProperty& p : e.properties)
          if (isVertexIndices(e, p)) return h;
      }
      std::set<std::string_view> xyz;
      if (vertex)
        for (const PlyProperty& p : vertex->properties) xyz.insert(p.name);
      if (!xyz.count("x") || !xyz.count("y") || !xyz.count("z"))
        r.fail(1, "", "PLY header without an element vertex with properties x, y and z");
      r.fail(1, "", "PLY header without an element face with a list property vertex_indices");
    }
    if (key == "comment" || key == "obj_info") continue;
    // OpenMesh splits the header at any white space (a form feed too) and loops forever when a
    // count is not a number: names are printable ASCII.
    for (const Token& w : t)
      if (!printable(w.text))
        r.fail(w.column, std::string(key),
               "unexpected bytes " + shown(w.text) + " in the PLY header");
    if (key == "format") {
      if (t.size() != 3 ||
          (t[1].text != "ascii" && t[1].text != "binary_little_endian" &&
           t[1].text != "binary_big_endian") ||
          t[2].text != "1.0")
        r.fail(t[0].column, "format",
               "expected ascii, binary_little_endian or binary_big_endian and version 1.0");
      h.format = t[1].text;
    } else if (key == "element") {
      if (t.size() != 3) r.fail(t[0].column, "element", "expected a name and a count");
      const long long count = integer(r, t[2], t[2].text, "element");
      if (count < 0) r.fail(t[2].column, "element", "expected a count of 0 or more");
      // Every element needs at least one byte, even in binary: counts beyond the file are corrupt.
      if (static_cast<unsigned long long>(count) > bytes.size())
        r.fail(t[2].column, "element",
               std::to_string(count) + " " + std::string(t[1].text) +
                   " elements, more than the file can hold");
      for (const PlyElement& e : h.elements)
        if (e.name == t[1].text && (e.name == "vertex" || e.name == "face"))
          r.fail(t[1].column, "element", "a second element " + e.name);
      h.elements.push_back({std::string(t[1].text), count, {}});
    } else if (key == "property") {
      if (h.elements.empty()) r.fail(t[0].column, "property", "a property before any element");
      PlyElement& e = h.elements.back();
      const bool list = t.size() >= 2 && t[1].text == "list";
      if (t.size() != (list ? 5u : 3u))
        r.fail(t[0].column, "property", "expected TYPE NAME or list TYPE TYPE NAME");
      for (size_t i = list ? 2 : 1; i + 1 < t.size(); ++i)
        if (!typeSizes().count(t[i].text))
          r.fail(t[i].column, "property", "unknown type " + shown(t[i].text));
      PlyProperty p{std::string(t.back().text), std::string(t[t.size() - 2].text),
                    list ? std::string(t[2].text) : std::string()};
      if (list && !isVertexIndices(e, p))
        r.fail(t[0].column, "property",
               "list property " + shown(p.name) + " in element " + shown(e.name) +
                   ": the only list read is the face's vertex_indices");
      if (list && p.countType != "uchar" && p.countType != "uint8" && p.countType != "uint16" &&
          p.countType != "int")
        r.fail(t[2].column, "property",
               "list count type " + shown(p.countType) + ": expected uchar, uint8, uint16 or int");
      if (list && isFloat(p.type))
        r.fail(t[3].column, "property", "vertex indices of type " + p.type + ": expected integers");
      if (h.format != "ascii" && readAsFloat(e.name, p.name) && !isFloat(p.type))
        r.fail(t[1].column, "property",
               "vertex property " + p.name + " of type " + p.type +
                   " in a binary PLY: expected float, float32, double or float64");
      e.properties.push_back(std::move(p));
    } else {
      r.fail(t[0].column, "", "unexpected " + shown(key) + " in the PLY header");
    }
  }
  r.fail(1, "", "truncated or malformed PLY header (no end_header)");
}

// The body's values one at a time, whichever the format; every problem names the element.
class BodyWalker {
 public:
  BodyWalker(std::string_view body, const PlyHeader& h, const std::filesystem::path& file)
      : body_(body),
        binary_(h.format != "ascii"),
        big_(h.format == "binary_big_endian"),
        file_(file.string()),
        line_(h.bodyLine) {}

  // The next value of `type`: integers must be integers in the type's range.
  double value(const std::string& type, const std::string& where) {
    if (binary_) return binaryValue(type, where);
    const Token t = token(where);
    const FileLoc loc{file_, line_, t.column};
    if (isFloat(type)) {
      double v = 0.0;
      const char* end = t.text.data() + t.text.size();
      const auto [ptr, ec] = std::from_chars(t.text.data(), end, v);
      // OpenMesh reads positions, normals and uv as floats, whatever the declared type.
      if (ptr != end || ec != std::errc() || !std::isfinite(v) || std::abs(v) > FLT_MAX)
        throw Error(loc, where, "expected a finite single-precision number, got " + shown(t.text));
      return v;
    }
    long long v = 0;
    const char* end = t.text.data() + t.text.size();
    const auto [ptr, ec] = std::from_chars(t.text.data(), end, v);
    if (ptr != end || ec != std::errc())
      throw Error(loc, where, "expected an integer (" + type + "), got " + shown(t.text));
    const int bits = 8 * typeSizes().at(type);
    const long long lo = isSigned(type) ? -(1LL << (bits - 1)) : 0;
    const long long hi = isSigned(type) ? (1LL << (bits - 1)) - 1 : (1LL << bits) - 1;
    if (v < lo || v > hi)
      throw Error(loc, where,
                  std::to_string(v) + " out of the range of " + type + " [" + std::to_string(lo) +
                      ", " + std::to_string(hi) + "]");
    return static_cast<double>(v);
  }

  // Values left at most (a bound for a list's length: every value takes a byte or a token).
  size_t left() const { return body_.size() - at_; }

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    if (binary_) throw Error(file_ + ": " + where + ": " + what);
    throw Error(FileLoc{file_, line_, 0}, where, what);
  }

 private:
  Token token(const std::string& where) {
    while (at_ < body_.size() && std::isspace(static_cast<unsigned char>(body_[at_]))) {
      if (body_[at_] == '\n') {
        ++line_;
        lineStart_ = at_ + 1;
      }
      ++at_;
    }
    if (at_ >= body_.size()) fail(where, "the file ends here (truncated PLY)");
    const size_t start = at_;
    while (at_ < body_.size() && !std::isspace(static_cast<unsigned char>(body_[at_]))) ++at_;
    return {body_.substr(start, at_ - start), static_cast<int>(start - lineStart_) + 1};
  }

  double binaryValue(const std::string& type, const std::string& where) {
    const int size = typeSizes().at(type);
    if (left() < static_cast<size_t>(size))
      fail(where, "the file ends here, " + std::to_string(static_cast<size_t>(size) - left()) +
                      " bytes short of its " + type + " (truncated PLY)");
    unsigned char b[8];
    std::memcpy(b, body_.data() + at_, size);
    at_ += size;
    if (big_) std::reverse(b, b + size);  // the bytes little-endian from here on
    uint64_t u = 0;
    for (int i = size - 1; i >= 0; --i) u = (u << 8) | b[i];
    if (type == "float" || type == "float32") {
      float f;
      const uint32_t u32 = static_cast<uint32_t>(u);
      std::memcpy(&f, &u32, 4);
      return f;
    }
    if (isFloat(type)) {
      double d;
      std::memcpy(&d, &u, 8);
      return d;
    }
    if (isSigned(type) && size < 8 && (u >> (8 * size - 1)))
      return static_cast<double>(static_cast<int64_t>(u) - (int64_t(1) << (8 * size)));
    return static_cast<double>(u);
  }

  std::string_view body_;
  bool binary_, big_;
  std::string file_;
  size_t at_ = 0, lineStart_ = 0;
  int line_;
};

std::string rewrite(const PlyHeader& h, std::string_view body) {
  std::string out = "ply\nformat " + h.format + " 1.0\n";
  for (const PlyElement& e : h.elements) {
    out += "element " + e.name + " " + std::to_string(e.count) + "\n";
    for (const PlyProperty& p : e.properties)
      out += p.countType.empty()
                 ? "property " + p.type + " " + p.name + "\n"
                 : "property list " + p.countType + " " + p.type + " " + p.name + "\n";
  }
  out += "end_header\n";
  return out.append(body);
}

}  // namespace

MeshTextCounts checkPly(std::string_view bytes, const std::filesystem::path& file) {
  const PlyHeader h = readHeader(bytes, file);
  const std::string_view body = bytes.substr(h.bodyOffset);
  BodyWalker walk(body, h, file);
  MeshTextCounts counts;
  counts.checked = true;
  // OpenMesh reads up to the face element and stops there.
  for (const PlyElement& e : h.elements) {
    if (e.properties.empty()) continue;
    for (long long i = 0; i < e.count; ++i)
      for (const PlyProperty& p : e.properties) {
        const std::string where = "element " + e.name + " " + std::to_string(i) + " " + p.name;
        if (p.countType.empty()) {
          walk.value(p.type, where);
          continue;
        }
        const double n = walk.value(p.countType, where);
        if (n < 3)
          walk.fail(where, "a face of " + std::to_string(static_cast<long long>(n)) +
                               " vertices: expected 3 or more");
        if (n > static_cast<double>(walk.left()))
          walk.fail(where, "a face of " + std::to_string(static_cast<long long>(n)) +
                               " vertices, more than the rest of the file can hold (truncated "
                               "or corrupt PLY)");
        std::set<double> seen;
        for (long long k = 0; k < static_cast<long long>(n); ++k) {
          const double vi = walk.value(p.type, where);
          if (vi < 0 || vi >= static_cast<double>(counts.vertices))
            walk.fail(where, "vertex index " + std::to_string(static_cast<long long>(vi)) +
                                 " out of range [0, " + std::to_string(counts.vertices) +
                                 ") (PLY counts from 0)");
          if (!seen.insert(vi).second)
            walk.fail(where, "vertex " + std::to_string(static_cast<long long>(vi)) +
                                 " appears twice in the face");
        }
      }
    if (e.name == "vertex") counts.vertices = e.count;
    if (e.name == "face") {
      counts.faces = e.count;
      break;
    }
  }
  counts.rewritten = rewrite(h, body);
  return counts;
}

}  // namespace meso
