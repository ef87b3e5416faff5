#include "meso/scene/mesh_text_check.h"

#include "meso/core/error.h"

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
  LineReader(std::string_view bytes, const std::filesystem::path& file) : bytes_(bytes), file_(file.string()) {}
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

long long integer(const LineReader& r, const Token& t, std::string_view text, const std::string& key) {
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
  if (raw == 0) r.fail(t.column, key, std::string("expected a ") + what + " index of 1 or more (OBJ counts from 1), got 0");
  const long long index = raw > 0 ? raw : defined + raw + 1;
  if (index < 1 || index > total)
    r.fail(t.column, key, std::string(what) + " index " + std::to_string(raw) + " out of range: the file has " +
                              std::to_string(raw > 0 ? total : defined) + " " + what + "s" +
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
  static const std::set<std::string_view> kKnown = {"vn", "vp", "o", "g", "s", "l", "p", "usemtl", "mtllib",
                                                   "cstype", "deg", "curv", "curv2", "surf", "parm", "end",
                                                   "trim", "hole", "scrv", "sp", "con", "mg", "bevel",
                                                   "c_interp", "d_interp", "lod", "shadow_obj", "trace_obj",
                                                   "ctech", "stech", "bmat", "step", "call", "csh", "maplib",
                                                   "usemap"};
  LineReader r(bytes, file);
  std::vector<Token> t;
  long long v = 0, vt = 0;
  while (r.next(t)) {
    const std::string_view key = t[0].text;
    if (key == "v") {
      if (t.size() < 4) r.fail(t[0].column, "v", "expected x y z, got " + std::to_string(t.size() - 1) + " numbers");
      for (size_t i = 1; i < t.size() && i <= 4; ++i) number(r, t[i], "v");
      ++v;
    } else if (key == "vt") {
      if (t.size() < 2) r.fail(t[0].column, "vt", "expected u [v [w]]");
      for (size_t i = 1; i < t.size() && i <= 3; ++i) number(r, t[i], "vt");
      ++vt;
    } else if (key == "f") {
      if (t.size() < 4)
        r.fail(t[0].column, "f", "expected a face of at least 3 vertices, got " + std::to_string(t.size() - 1));
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
        r.fail(t[0].column, "", "unexpected bytes " + shown(key) + " (not an OBJ statement: corrupt or binary file?)");
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
  const std::string_view magic = t[0].text;
  // Binary, homogeneous (4OFF) and n-dimensional (nOFF) variants are left to OpenMesh.
  if (magic.size() < 3 || magic.substr(magic.size() - 3) != "OFF" || magic.find('4') != std::string_view::npos ||
      magic.find('n') != std::string_view::npos || (t.size() > 1 && t[1].text == "BINARY"))
    return counts;
  std::vector<Token> header(t.begin() + 1, t.end());
  if (header.empty() && !r.next(header)) r.fail(1, "", "truncated OFF: expected the vertex, face and edge counts");
  if (header.size() < 2) r.fail(header[0].column, "", "expected the vertex, face and edge counts");
  const long long nv = integer(r, header[0], header[0].text, "vertex count");
  const long long nf = integer(r, header[1], header[1].text, "face count");
  if (nv < 0 || nf < 0) r.fail(header[0].column, "", "expected counts of 0 or more");
  if (nf == 0) throw Error(file.string() + ": mesh has no faces (the OFF header declares 0)");
  counts.checked = true;
  const auto truncated = [&](const char* what, int line) {
    throw Error(file.string() + ": truncated OFF: the header declares " + std::to_string(nv) + " vertices and " +
                std::to_string(nf) + " faces; the file ends after " + std::to_string(counts.vertices) +
                " vertices and " + std::to_string(counts.faces) + " faces (expected " + what + " at line " +
                std::to_string(line) + ")");
  };
  for (; counts.vertices < nv; ++counts.vertices) {
    if (!r.next(t)) truncated("a vertex", r.line() + 1);
    if (t.size() < 3 && r.atEnd()) truncated("a vertex", r.line());
    if (t.size() < 3)
      r.fail(t[0].column, "vertex " + std::to_string(counts.vertices),
             "expected x y z, got " + std::to_string(t.size()) + " numbers");
    for (size_t i = 0; i < 3; ++i) number(r, t[i], "vertex " + std::to_string(counts.vertices));
  }
  for (; counts.faces < nf; ++counts.faces) {
    if (!r.next(t)) truncated("a face", r.line() + 1);
    const std::string key = "face " + std::to_string(counts.faces);
    const long long n = integer(r, t[0], t[0].text, key);
    if (n < 3) r.fail(t[0].column, key, "expected a face size of 3 or more, got " + std::to_string(n));
    if (static_cast<long long>(t.size()) - 1 < n && r.atEnd()) truncated("a whole face", r.line());
    if (static_cast<long long>(t.size()) - 1 < n)
      r.fail(t[0].column, key, "face size " + std::to_string(n) + " but " + std::to_string(t.size() - 1) +
                                   " indices on the line");
    std::set<long long> seen;
    for (long long i = 1; i <= n; ++i) {
      const long long vi = integer(r, t[i], t[i].text, key);
      if (vi < 0 || vi >= nv)
        r.fail(t[i].column, key, "vertex index " + std::to_string(vi) + " out of range [0, " + std::to_string(nv) +
                                     ") (OFF counts from 0)");
      if (!seen.insert(vi).second) r.fail(t[i].column, key, "vertex " + std::to_string(vi) + " appears twice in the face");
    }
  }
  return counts;
}

}  // namespace

MeshTextCounts checkMeshText(std::string_view bytes, const std::filesystem::path& file, const std::string& ext) {
  if (ext == ".obj") return checkObj(bytes, file);
  if (ext == ".off") return checkOff(bytes, file);
  return {};
}

}  // namespace meso
