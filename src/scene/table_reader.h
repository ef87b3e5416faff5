// The scene reader's view of one TOML table (docs/scene-format.md): typed, range-checked keys, each
// rejected value named FILE:LINE:COL: key: what was expected, and keys no reader asked for refused.
// Private to src/scene.
#pragma once

#include "meso/core/error.h"
#include "meso/core/math.h"
#include "meso/scene/choices.h"

#include <toml++/toml.h>

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace meso {

// "a string", "3", "a table", ...: what a node holds, for error messages.
std::string describe(const toml::node& n);

class TableReader {
 public:
  TableReader(const toml::table& table, std::string prefix, const std::string& file)
      : table_(table), prefix_(std::move(prefix)), file_(file) {}

  [[noreturn]] void fail(const toml::node& n, const std::string& key,
                         const std::string& what) const {
    throw Error(loc(n), prefix_ + key, what);
  }
  // A node set on the command line (SceneOverride) carries its option as its source path.
  FileLoc loc(const toml::node& n) const {
    if (const auto& path = n.source().path; path && *path != file_) return {*path};
    return {file_, static_cast<int>(n.source().begin.line),
            static_cast<int>(n.source().begin.column)};
  }
  // Where the table itself starts (its [header] line): for errors about a key it lacks.
  FileLoc tableLoc() const { return loc(table_); }
  std::string dotted(const std::string& key) const { return prefix_ + key; }
  const std::string& file() const { return file_; }
  const std::string& prefix() const { return prefix_; }

  // The node of `key` (nullptr if absent); marks the key as known.
  const toml::node* get(const std::string& key) {
    allowed_.insert(key);
    return table_.get(key);
  }

  double number(const std::string& key, double fallback, double lo, double hi, bool openLo = false,
                bool openHi = false);
  double checkedNumber(const toml::node& n, const std::string& key, double lo, double hi,
                       bool openLo, bool openHi) const;
  int64_t integer(const std::string& key, int64_t fallback, int64_t lo, int64_t hi);
  bool boolean(const std::string& key, bool fallback);
  std::optional<std::string> string(const std::string& key);
  // One of `allowed`, else an error listing them.
  std::string choice(const std::string& key, const std::string& fallback,
                     const std::vector<std::string>& allowed);
  // A name from Choices<E> (choices.h), converted here, else an error listing the names.
  template <class E>
  E choice(const std::string& key, E fallback) {
    const std::optional<std::string> v = string(key);
    if (!v) return fallback;
    if (const std::optional<E> e = parseChoice<E>(*v)) return *e;
    fail(*get(key), key, "expected one of " + choiceList<E>() + ", got \"" + *v + "\"");
  }
  // An array of exactly `size` numbers, each within [lo, hi].
  std::vector<double> numbers(const toml::node& n, const std::string& key, size_t size, double lo,
                              double hi) const;
  Vec3 vec3(const std::string& key, Vec3 fallback, double lo = -1e30, double hi = 1e30);
  // A number (grey) or [r, g, b], each >= 0.
  Vec3 colour(const std::string& key, Vec3 fallback, double hi = 1e6);
  const toml::table* subtable(const std::string& key);
  // The tables of an array of tables ([[key]]).
  std::vector<const toml::table*> tableArray(const std::string& key);
  // Rejects every key that no reader asked for, naming the allowed ones.
  void finish() const;

 private:
  const toml::table& table_;
  std::string prefix_;
  const std::string& file_;
  std::set<std::string> allowed_;
};

}  // namespace meso
