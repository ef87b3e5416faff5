// The line reader and token checks shared by the OBJ, OFF and PLY checks (mesh_text_check.cpp,
// ply_check.cpp). Internal to src/scene.
#pragma once

#include "meso/core/error.h"

#include <cfloat>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace meso::mesh_text {

struct Token {
  std::string_view text;
  int column;  // 1-based
};

// The whitespace-separated tokens of a line, up to a '#' comment, into `tokens` (its storage
// reused from line to line).
inline void tokenize(std::string_view line, std::vector<Token>& tokens) {
  tokens.clear();
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    if (i >= line.size() || line[i] == '#') break;
    const size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    tokens.push_back({line.substr(start, i - start), static_cast<int>(start) + 1});
  }
}

inline std::string shown(std::string_view t) {
  std::string s(t.substr(0, 40));
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
  return "\"" + s + (t.size() > 40 ? "...\"" : "\"");
}

inline bool printable(std::string_view t) {
  for (char c : t)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) return false;
  return true;
}

class LineReader {
 public:
  // `lines`: the lines before `bytes` in the file (a chunk of it), which line numbers count from.
  LineReader(std::string_view bytes, const std::filesystem::path& file, int lines = 0)
      : bytes_(bytes), file_(file.string()), line_(lines) {}
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
      tokenize(line, tokens);
      if (!tokens.empty()) return true;
    }
    return false;
  }
  [[noreturn]] void fail(int column, const std::string& key, const std::string& what) const {
    throw Error(FileLoc{file_, line_, column}, key, what);
  }
  int line() const { return line_; }
  // Where the next line starts in the bytes.
  size_t offset() const { return at_; }
  bool atEnd() const { return done_; }

 private:
  std::string_view bytes_;
  std::string file_;
  size_t at_ = 0;
  int line_ = 0;
  bool done_ = false;
};

inline double number(const LineReader& r, const Token& t, const std::string& key) {
  double v = 0.0;
  const char* end = t.text.data() + t.text.size();
  const auto [ptr, ec] = std::from_chars(t.text.data(), end, v);
  if (ptr != end || (ec != std::errc() && ec != std::errc::result_out_of_range))
    r.fail(t.column, key, "expected a number, got " + shown(t.text));
  if (ec == std::errc::result_out_of_range || !std::isfinite(v) || std::abs(v) > FLT_MAX)
    r.fail(t.column, key, "expected a finite single-precision number, got " + shown(t.text));
  return v;
}

inline long long integer(const LineReader& r, const Token& t, std::string_view text,
                         const std::string& key) {
  long long v = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ptr != end || ec != std::errc())
    r.fail(t.column, key, "expected an integer index, got " + shown(text));
  return v;
}

}  // namespace meso::mesh_text
