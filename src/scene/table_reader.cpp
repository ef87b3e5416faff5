// Typed, range-checked keys of one TOML table (see table_reader.h).
#include "table_reader.h"

#include <cmath>
#include <sstream>

namespace meso {

std::string describe(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return std::to_string(n.as_integer()->get());
    case toml::node_type::floating_point: {
      std::ostringstream s;
      s << n.as_floating_point()->get();
      return s.str();
    }
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::table:
      return "a table";
    default:
      return "a date or time";
  }
}

double TableReader::number(const std::string& key, double fallback, double lo, double hi,
                           bool openLo, bool openHi) {
  const toml::node* n = get(key);
  return n ? checkedNumber(*n, key, lo, hi, openLo, openHi) : fallback;
}

double TableReader::checkedNumber(const toml::node& n, const std::string& key, double lo, double hi,
                                  bool openLo, bool openHi) const {
  if (!n.is_number()) fail(n, key, "expected a number, got " + describe(n));
  const double v =
      n.is_integer() ? static_cast<double>(n.as_integer()->get()) : n.as_floating_point()->get();
  if (!std::isfinite(v)) fail(n, key, "expected a finite number, got " + describe(n));
  if ((openLo ? v <= lo : v < lo) || (openHi ? v >= hi : v > hi)) {
    std::ostringstream s;
    s << "expected a number in " << (openLo ? "(" : "[") << lo << ", " << hi << (openHi ? ")" : "]")
      << ", got " << describe(n);
    fail(n, key, s.str());
  }
  return v;
}

int64_t TableReader::integer(const std::string& key, int64_t fallback, int64_t lo, int64_t hi) {
  const toml::node* n = get(key);
  if (!n) return fallback;
  if (!n->is_integer()) fail(*n, key, "expected an integer, got " + describe(*n));
  const int64_t v = n->as_integer()->get();
  if (v < lo || v > hi)
    fail(*n, key,
         "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
             std::to_string(v));
  return v;
}

bool TableReader::boolean(const std::string& key, bool fallback) {
  const toml::node* n = get(key);
  if (!n) return fallback;
  if (!n->is_boolean()) fail(*n, key, "expected true or false, got " + describe(*n));
  return n->as_boolean()->get();
}

std::optional<std::string> TableReader::string(const std::string& key) {
  const toml::node* n = get(key);
  if (!n) return std::nullopt;
  if (!n->is_string()) fail(*n, key, "expected a string, got " + describe(*n));
  return n->as_string()->get();
}

std::string TableReader::choice(const std::string& key, const std::string& fallback,
                                const std::vector<std::string>& allowed) {
  const std::optional<std::string> v = string(key);
  if (!v) return fallback;
  for (const std::string& a : allowed)
    if (*v == a) return *v;
  std::string list;
  for (const std::string& a : allowed) list += (list.empty() ? "" : " | ") + a;
  fail(*get(key), key, "expected one of " + list + ", got \"" + *v + "\"");
}

std::vector<double> TableReader::numbers(const toml::node& n, const std::string& key, size_t size,
                                         double lo, double hi) const {
  const toml::array* a = n.as_array();
  if (!a || a->size() != size)
    fail(n, key,
         "expected an array of " + std::to_string(size) + " numbers, got " +
             (a ? "an array of " + std::to_string(a->size()) : describe(n)));
  std::vector<double> out;
  for (const toml::node& e : *a) out.push_back(checkedNumber(e, key, lo, hi, false, false));
  return out;
}

Vec3 TableReader::vec3(const std::string& key, Vec3 fallback, double lo, double hi) {
  const toml::node* n = get(key);
  if (!n) return fallback;
  const std::vector<double> v = numbers(*n, key, 3, lo, hi);
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

Vec3 TableReader::colour(const std::string& key, Vec3 fallback, double hi) {
  const toml::node* n = get(key);
  if (!n) return fallback;
  if (n->is_number())
    return Vec3(static_cast<float>(checkedNumber(*n, key, 0.0, hi, false, false)));
  if (!n->is_array())
    fail(*n, key, "expected a number or an array [r, g, b] of numbers >= 0, got " + describe(*n));
  const std::vector<double> v = numbers(*n, key, 3, 0.0, hi);
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

const toml::table* TableReader::subtable(const std::string& key) {
  const toml::node* n = get(key);
  if (!n) return nullptr;
  if (!n->is_table()) fail(*n, key, "expected a table, got " + describe(*n));
  return n->as_table();
}

std::vector<const toml::table*> TableReader::tableArray(const std::string& key) {
  const toml::node* n = get(key);
  std::vector<const toml::table*> out;
  if (!n) return out;
  const toml::array* a = n->as_array();
  if (!a)
    fail(*n, key, "expected an array of tables ([[" + dotted(key) + "]]), got " + describe(*n));
  for (const toml::node& e : *a) {
    if (!e.is_table()) fail(e, key, "expected a table, got " + describe(e));
    out.push_back(e.as_table());
  }
  return out;
}

void TableReader::finish() const {
  for (auto&& [k, v] : table_) {
    const std::string key(k.str());
    if (allowed_.count(key)) continue;
    std::string list;
    for (const std::string& a : allowed_) list += (list.empty() ? "" : ", ") + a;
    const FileLoc at{file_, static_cast<int>(k.source().begin.line),
                     static_cast<int>(k.source().begin.column)};
    throw Error(at.line > 0 ? at : loc(v), prefix_ + key,
                "unknown key (allowed here: " + list + ")");
  }
}

}  // namespace meso
