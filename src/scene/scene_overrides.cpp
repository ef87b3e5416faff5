// Scene keys set from the command line (scene_overrides.h).
#include "scene_overrides.h"

#include "table_reader.h"

#include "meso/core/error.h"

#include <charconv>
#include <optional>
#include <string>
#include <vector>

namespace meso {
namespace {

// One step of a key: a table's key, and with `materials[1]` an index into the array it names.
struct KeyPart {
  std::string name;
  std::optional<size_t> index;
};

bool isBareKeyChar(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '-';
}

[[noreturn]] void fail(const SceneOverride& o, const std::string& key, const std::string& what) {
  throw Error(FileLoc{o.origin}, key, what);
}

std::vector<KeyPart> splitKey(const SceneOverride& o) {
  const std::string expected =
      "expected a dotted scene key such as camera.fov, render.D or materials[1].kd, got \"" +
      o.key + "\"";
  std::vector<KeyPart> parts;
  size_t at = 0;
  while (true) {
    KeyPart p;
    while (at < o.key.size() && isBareKeyChar(o.key[at])) p.name += o.key[at++];
    if (p.name.empty()) fail(o, "", expected);
    if (at < o.key.size() && o.key[at] == '[') {
      const size_t close = o.key.find(']', at);
      size_t i = 0;
      const char* first = o.key.data() + at + 1;
      const char* last = o.key.data() + (close == std::string::npos ? o.key.size() : close);
      const auto [end, ec] = std::from_chars(first, last, i);
      if (close == std::string::npos || first == last || ec != std::errc() || end != last)
        fail(o, "", expected);
      p.index = i;
      at = close + 1;
    }
    parts.push_back(std::move(p));
    if (at == o.key.size()) return parts;
    if (o.key[at] != '.') fail(o, "", expected);
    ++at;
  }
}

// A word such as bump or meshes/rock.obj that TOML would want quoted: taken as that string.
bool isBareString(const std::string& v) {
  if (v.empty() || (v[0] >= '0' && v[0] <= '9') || v[0] == '+' || v[0] == '-') return false;
  for (char c : v)
    if (std::string_view("\"'[]{}=,# \t\n\r").find(c) != std::string_view::npos) return false;
  return true;
}

// A table whose "value" is the override's value, every node of it with the origin as its source.
toml::table parseValue(const SceneOverride& o) {
  const std::string_view origin(o.origin);
  std::string problem;
  try {
    return toml::parse("value = " + o.value, origin);
  } catch (const toml::parse_error& e) {
    problem = e.description();
  }
  // A literal string takes every character but ', line breaks and control characters as it is.
  if (isBareString(o.value)) {
    try {
      return toml::parse("value = '" + o.value + "'", origin);
    } catch (const toml::parse_error&) {
    }
  }
  fail(o, o.key,
       "expected a TOML value (1.5, [320, 180], true, \"text\"), got " + o.value + " (" + problem +
           ")");
}

// Moves `value` into `table` under `name` (moved: a copied node forgets its source).
void setIn(toml::table& table, const std::string& name, toml::node& value) {
  value.visit([&](auto& v) { table.insert_or_assign(name, std::move(v)); });
}

// The table at `name` in `table`, created (with the origin as its source) when absent.
toml::table& tableIn(toml::table& table, const std::string& name, const SceneOverride& o,
                     const std::string& walked) {
  if (!table.contains(name)) {
    toml::table empty = toml::parse("value = {}", std::string_view(o.origin));
    setIn(table, name, *empty.get("value"));
  }
  toml::node& n = *table.get(name);
  if (!n.is_table())
    fail(o, walked, "expected a table to set " + o.key + " in, got " + describe(n));
  return *n.as_table();
}

// The element `index` of the array of tables at `name` in `table`.
toml::array& arrayIn(toml::table& table, const std::string& name, size_t index,
                     const SceneOverride& o, const std::string& walked) {
  toml::array* a = table.get(name) ? table.get(name)->as_array() : nullptr;
  const size_t size = a ? a->size() : 0;
  if (index >= size)
    fail(o, walked,
         "expected an index below " + std::to_string(size) + " (the scene has " +
             std::to_string(size) + " [[" + walked + "]] entries), got " + std::to_string(index));
  return *a;
}

void apply(toml::table& top, const SceneOverride& o) {
  const std::vector<KeyPart> parts = splitKey(o);
  toml::table parsed = parseValue(o);
  toml::node& value = *parsed.get("value");
  toml::table* table = &top;
  std::string walked;
  for (size_t k = 0; k < parts.size(); ++k) {
    const KeyPart& p = parts[k];
    const bool last = k + 1 == parts.size();
    walked += (k > 0 ? "." : "") + p.name;
    if (!p.index) {
      if (last) return setIn(*table, p.name, value);
      table = &tableIn(*table, p.name, o, walked);
      continue;
    }
    toml::array& a = arrayIn(*table, p.name, *p.index, o, walked);
    const auto at = a.cbegin() + static_cast<std::ptrdiff_t>(*p.index);
    walked.append("[").append(std::to_string(*p.index)).append("]");
    if (last) {
      value.visit([&](auto& v) { a.replace(at, std::move(v)); });
      return;
    }
    toml::node& e = *a.get(*p.index);
    if (!e.is_table())
      fail(o, walked, "expected a table to set " + o.key + " in, got " + describe(e));
    table = e.as_table();
  }
}

}  // namespace

void applySceneOverrides(toml::table& top, std::span<const SceneOverride> overrides) {
  for (const SceneOverride& o : overrides) apply(top, o);
}

}  // namespace meso
