// Reads a scene file's [[materials]] (material_reader.h).
#include "material_reader.h"

#include <toml++/toml.h>

#include <cstdint>
#include <fstream>
#include <optional>
#include <vector>

namespace meso {

std::filesystem::path readablePath(TableReader& r, const std::string& key,
                                   const std::filesystem::path& base) {
  const std::optional<std::string> s = r.string(key);
  const toml::node& n = *r.get(key);
  if (s->empty()) r.fail(n, key, "expected a file name, got an empty string");
  const std::filesystem::path p =
      std::filesystem::path(*s).is_absolute() ? std::filesystem::path(*s) : base / *s;
  std::error_code ec;
  if (!std::filesystem::exists(p, ec)) r.fail(n, key, "file not found: " + p.string());
  if (!std::filesystem::is_regular_file(p, ec)) r.fail(n, key, "not a regular file: " + p.string());
  if (!std::ifstream(p).good()) r.fail(n, key, "cannot read file: " + p.string());
  return p;
}

namespace {

// One [[materials.relief]] table: one level, or with split_octaves = true one level per octave of
// its noise (heights that add up to the whole fBm exactly; each level gets its own T). A height
// image's bands are planned when the scene is loaded (relief_bands.h), not parsed: parsing reads
// no image.
std::vector<ReliefLevelDecl> readRelief(TableReader& r, const toml::table& t,
                                        const std::filesystem::path& base) {
  ReliefLevelDecl d;
  d.loc = {r.file(), static_cast<int>(t.source().begin.line),
           static_cast<int>(t.source().begin.column)};
  const bool hasHeight = t.contains("height"), hasNoise = t.contains("noise"),
             hasSolid = t.contains("solid");
  if (int(hasHeight) + int(hasNoise) + int(hasSolid) != 1)
    throw Error(d.loc, r.prefix() + "height",
                "expected exactly one of `height` (an image file), `noise` (a table) or `solid` "
                "(a table: noise in 3-D space)");
  if (hasHeight) {
    d.source = ReliefSource::Image;
    d.height = readablePath(r, "height", base);
    d.periodic = r.choice("wrap", "periodic", {"periodic", "clamp"}) == "periodic";
  } else {
    d.source = hasSolid ? ReliefSource::Solid : ReliefSource::Noise;
    const char* key = hasSolid ? "solid" : "noise";
    TableReader n(*r.subtable(key), r.prefix() + key + ".", r.file());
    d.octaves = static_cast<int>(n.integer("octaves", d.octaves, 1, 16));
    d.lacunarity = static_cast<float>(n.number("lacunarity", d.lacunarity, 1.0, 16.0));
    d.gain = static_cast<float>(n.number("gain", d.gain, 0.0, 1.0));
    d.seed = static_cast<uint64_t>(n.integer("seed", 0, 0, INT64_MAX));
    if (hasSolid)
      d.worldSpace = n.choice("space", "object", {"object", "world"}) == "world";
    else
      d.periodic = n.boolean("periodic", d.periodic);
    n.finish();
  }
  if (hasHeight) d.bands = static_cast<int>(r.integer("bands", 0, 0, 16));
  d.amplitude = static_cast<float>(r.number("amplitude", d.amplitude, 0.0, 1e6));
  d.scale = static_cast<float>(r.number("scale", d.scale, 0.0, 1e6, true));
  d.freq = static_cast<float>(r.number("freq", d.freq, 0.0, 1e6));
  if (r.get("midlevel")) d.midlevel = static_cast<float>(r.number("midlevel", 0.0, -1e6, 1e6));
  const bool split = r.boolean("split_octaves", false);
  if (hasHeight && d.freq > 0.0f) {  // a hand-set frequency is the whole image's: one level
    if (d.bands > 1)
      throw Error(r.loc(*r.get("freq")), r.prefix() + "freq",
                  "freq is the frequency of one level; with bands each band's is measured: drop "
                  "freq, or set bands = 1");
    d.bands = 1;
  }
  r.finish();
  if (!split) return {d};
  const auto refuse = [&](const char* key, const char* why) {
    throw Error(d.loc, r.prefix() + key, why);
  };
  if (d.source == ReliefSource::Image)
    refuse("split_octaves",
           "split_octaves splits a noise relief; a height image is split into octave bands by "
           "`bands`");
  if (d.midlevel)
    refuse("midlevel", "split_octaves gives each octave its own mean as midlevel: drop midlevel");
  if (d.freq > 0.0f) refuse("freq", "split_octaves knows each octave's frequency: drop freq");
  std::vector<ReliefLevelDecl> out;
  for (int o = 0; o < d.octaves; ++o) {
    out.push_back(d);
    out.back().firstOctave = o;
    out.back().octaves = o + 1;
  }
  return out;
}

NdfDecl readNdf(TableReader& r, const toml::table& t, const std::filesystem::path& base) {
  NdfDecl d;
  d.present = true;
  d.loc = {r.file(), static_cast<int>(t.source().begin.line),
           static_cast<int>(t.source().begin.column)};
  d.type = r.choice("type", d.type);
  if (const toml::node* a = r.get("alpha")) {
    if (a->is_array()) {
      const std::vector<double> v = r.numbers(*a, "alpha", 2, 1e-4, 10.0);
      d.alpha = Vec2(static_cast<float>(v[0]), static_cast<float>(v[1]));
    } else {
      d.alpha = Vec2(static_cast<float>(r.number("alpha", 0.3, 1e-4, 10.0)));
    }
  }
  d.angle = static_cast<float>(r.number("angle", d.angle, -360.0, 360.0));
  d.exponent = static_cast<float>(r.number("exponent", d.exponent, 0.0, 1e6, true));
  if (d.type == NdfType::Tabulated) {
    if (!r.get("image"))
      throw Error(d.loc, r.prefix() + "image",
                  "a tabulated NDF needs `image` (an NDF over n.x, n.y)");
    d.image = readablePath(r, "image", base);
  }
  d.scale = static_cast<float>(r.number("scale", d.scale, 0.0, 1e9));
  d.octaves = static_cast<int>(r.integer("octaves", d.octaves, 1, 24));
  d.lacunarity = static_cast<float>(r.number("lacunarity", d.lacunarity, 1.0, 16.0, true));
  d.gain = static_cast<float>(r.number("gain", d.gain, 0.0, 1.0, true));
  d.seed = static_cast<uint64_t>(r.integer("seed", 0, 0, INT64_MAX));
  d.lambert = r.boolean("lambert", d.lambert);
  r.finish();
  return d;
}

}  // namespace

Material readMaterial(TableReader& r, const std::filesystem::path& base) {
  Material m;
  const std::optional<std::string> name = r.string("name");
  if (!name || name->empty())
    throw Error(name ? r.loc(*r.get("name")) : r.tableLoc(), r.prefix() + "name",
                "every material needs a non-empty name");
  m.name = *name;
  m.loc = r.loc(*r.get("name"));
  m.ka = r.colour("ka", m.ka);
  // kd and ks: a colour, or a colour image's file name (read with its colour space when the
  // scene is loaded; render/colour_textures.h).
  const auto colourOrImage = [&](const char* key, Vec3& colour, ColourTexture& texture) {
    const toml::node* n = r.get(key);
    if (n && n->is_string()) {
      texture.file = readablePath(r, key, base);
      texture.loc = r.loc(*n);
      colour = Vec3(1.0f);
    } else {
      colour = r.colour(key, colour);
    }
  };
  colourOrImage("kd", m.kd, m.kdTexture);
  colourOrImage("ks", m.ks, m.ksTexture);
  m.kdTexture.space = m.ksTexture.space = r.choice("colour_space", ColourSpace::Auto);
  m.phong = static_cast<float>(r.number("phong", m.phong, 0.0, 10000.0));
  const std::vector<const toml::table*> levels = r.tableArray("relief");
  if (levels.size() > static_cast<size_t>(kMaxMaterialReliefLevels))
    throw Error(r.loc(*r.get("relief")), r.prefix() + "relief",
                "at most " + std::to_string(kMaxMaterialReliefLevels) +
                    " relief levels per material (got " + std::to_string(levels.size()) + ")");
  for (const toml::table* t : levels) {
    TableReader rr(*t, r.prefix() + "relief.", r.file());
    for (ReliefLevelDecl& d : readRelief(rr, *t, base)) m.relief.push_back(std::move(d));
  }
  if (m.relief.size() > static_cast<size_t>(kMaxMaterialReliefLevels))
    throw Error(r.loc(*r.get("relief")), r.prefix() + "relief",
                "at most " + std::to_string(kMaxMaterialReliefLevels) +
                    " relief levels per material, counting each octave of split_octaves (got " +
                    std::to_string(m.relief.size()) + ")");
  // Solid relief replaces the parameterization at every point by a local unit-speed chart
  // (docs/solid-relief.md): the levels of a material are all solid, in one space, or none.
  for (const ReliefLevelDecl& d : m.relief)
    if ((d.source == ReliefSource::Solid) != (m.relief.front().source == ReliefSource::Solid) ||
        d.worldSpace != m.relief.front().worldSpace)
      throw Error(d.loc, r.prefix() + "relief",
                  "a material's relief levels are all `solid` (in one `space`) or none: solid "
                  "relief has no (u, v) for the other levels to follow");
  const bool solid = !m.relief.empty() && m.relief.front().source == ReliefSource::Solid;
  if (const toml::table* t = r.subtable("ndf")) {
    if (solid)
      throw Error(r.loc(*r.get("ndf")), r.prefix() + "ndf",
                  "[materials.ndf] synthesizes detail over (u, v), which solid relief does not "
                  "use: drop it, or use `noise` relief");
    TableReader nr(*t, r.prefix() + "ndf.", r.file());
    m.ndf = readNdf(nr, *t, base);
    if (m.ndf.type == NdfType::Relief && m.relief.empty())
      throw Error(m.ndf.loc, r.prefix() + "ndf.type",
                  "\"relief\" estimates the NDF from the material's finest relief level, "
                  "but the material has no [[materials.relief]]");
  }
  r.finish();
  return m;
}

}  // namespace meso
