// Errors with a source location: "FILE:LINE:COL: key: message" or "FILE: message".
#pragma once

#include <stdexcept>
#include <string>

namespace meso {

// Where in an input file something was found. line and column are 1-based; 0 means unknown.
struct FileLoc {
  std::string file;
  int line = 0;
  int column = 0;
};

// The one exception type of meso for bad input. The CLI prints what() and exits with status 2.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
  // "FILE:LINE:COL: key: message" (key and line/column omitted when empty or 0).
  Error(const FileLoc& loc, const std::string& key, const std::string& message)
      : std::runtime_error(format(loc, key, message)), loc_(loc) {}

  const FileLoc& where() const { return loc_; }

  static std::string format(const FileLoc& loc, const std::string& key,
                            const std::string& message) {
    // append() rather than operator+ chains: GCC 12 warns falsely (-Wrestrict) on the latter.
    std::string s = loc.file;
    if (loc.line > 0) {
      s.append(":").append(std::to_string(loc.line));
      if (loc.column > 0) s.append(":").append(std::to_string(loc.column));
    }
    if (!s.empty()) s.append(": ");
    if (!key.empty()) s.append(key).append(": ");
    return s.append(message);
  }

 private:
  FileLoc loc_;
};

}  // namespace meso
