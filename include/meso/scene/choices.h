// The named choices of a scene file and the command line (render.algorithm, render.normals,
// render.dicing_metric, render.tables.variant, a relief level's source, materials.ndf.type,
// lights.type, objects.scheme; `meso consistency --component` and `--format`): one enum each and
// one table of its names, used by the scene reader, the CLI and the messages. Strings die where
// they are parsed (pbrt-v4's way): an unknown name is an error there, never a silent default.
#pragma once

#include "meso/core/texture_lookup.h"  // ColourSpace (materials.colour_space)

#include "meso/geometry/control_mesh.h"   // SubdivisionScheme
#include "meso/geometry/dicing_metric.h"  // DicingMetric

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace meso {

// render.algorithm: the hybrid of Becker & Max 1993 (auto) or one renderer everywhere.
enum class Algorithm { Auto, Brdf, Bump, Redistribution, Displacement };

// render.normals: the shading normal on displaced geometry.
enum class ShadingNormals {
  Bump,   // the limit surface's normal bumped by the relief's slopes (the paper's)
  Facet,  // the micropolygon's geometric normal
};

// render.tables.variant: how the redistribution maps are built (DESIGN.md section 4).
enum class RedistributionVariant {
  Separable,    // theta_N and phi mapped by their marginals, independently (the paper's maps)
  Conditional,  // phi by its marginal first, then theta_N by its distribution at that phi,
                // interpolated linearly between phi-bin centres so the map is continuous
                // (meso's default: see TableSettings)
};

// Where a relief level's heights come from: `height` (an image file) or `noise` (a table).
enum class ReliefSource { Image, Noise, Solid };

// materials.ndf.type: the finest level's NDF (docs/synthesis.md).
enum class NdfType { Beckmann, BlinnPhong, Tabulated, Relief };

// lights.type. An environment is light from every direction (Scene::environment).
enum class LightType { Directional, Point, Environment };

// `meso consistency --component`: the terms of the local model the patch is lit with (kd = 1,
// ks = 1 or both; ka = 0).
enum class Component { Diffuse, Specular, Both };

// `meso consistency --format`: how its tables are printed.
enum class TableFormat { Csv, Markdown };

template <class E>
struct ChoiceName {
  E value;
  const char* name;
};

// Choices<E>::names lists every value of E with its name, in the order messages list them.
template <class E>
struct Choices;

template <>
struct Choices<Algorithm> {
  static constexpr std::array<ChoiceName<Algorithm>, 5> names{
      {{Algorithm::Auto, "auto"},
       {Algorithm::Brdf, "brdf"},
       {Algorithm::Bump, "bump"},
       {Algorithm::Redistribution, "redistribution"},
       {Algorithm::Displacement, "displacement"}}};
};
template <>
struct Choices<ShadingNormals> {
  static constexpr std::array<ChoiceName<ShadingNormals>, 2> names{
      {{ShadingNormals::Bump, "bump"}, {ShadingNormals::Facet, "facet"}}};
};
template <>
struct Choices<RedistributionVariant> {
  static constexpr std::array<ChoiceName<RedistributionVariant>, 2> names{
      {{RedistributionVariant::Conditional, "conditional"},
       {RedistributionVariant::Separable, "separable"}}};
};
template <>
struct Choices<ReliefSource> {
  static constexpr std::array<ChoiceName<ReliefSource>, 3> names{{{ReliefSource::Image, "image"},
                                                                  {ReliefSource::Noise, "noise"},
                                                                  {ReliefSource::Solid, "solid"}}};
};
template <>
struct Choices<ColourSpace> {
  static constexpr std::array<ChoiceName<ColourSpace>, 3> names{
      {{ColourSpace::Auto, "auto"}, {ColourSpace::Srgb, "srgb"}, {ColourSpace::Linear, "linear"}}};
};
template <>
struct Choices<NdfType> {
  static constexpr std::array<ChoiceName<NdfType>, 4> names{{{NdfType::Beckmann, "beckmann"},
                                                             {NdfType::BlinnPhong, "blinn-phong"},
                                                             {NdfType::Tabulated, "tabulated"},
                                                             {NdfType::Relief, "relief"}}};
};
template <>
struct Choices<LightType> {
  static constexpr std::array<ChoiceName<LightType>, 3> names{
      {{LightType::Directional, "directional"},
       {LightType::Point, "point"},
       {LightType::Environment, "environment"}}};
};
template <>
struct Choices<DicingMetric> {
  static constexpr std::array<ChoiceName<DicingMetric>, 2> names{
      {{DicingMetric::Isotropic, "isotropic"}, {DicingMetric::Projected, "projected"}}};
};
template <>
struct Choices<Component> {
  static constexpr std::array<ChoiceName<Component>, 3> names{{{Component::Diffuse, "diffuse"},
                                                               {Component::Specular, "specular"},
                                                               {Component::Both, "both"}}};
};
template <>
struct Choices<TableFormat> {
  static constexpr std::array<ChoiceName<TableFormat>, 2> names{
      {{TableFormat::Csv, "csv"}, {TableFormat::Markdown, "markdown"}}};
};
template <>
struct Choices<SubdivisionScheme> {
  static constexpr std::array<ChoiceName<SubdivisionScheme>, 3> names{
      {{SubdivisionScheme::CatmullClark, "catmull-clark"},
       {SubdivisionScheme::Loop, "loop"},
       {SubdivisionScheme::Bilinear, "bilinear"}}};
};

// The name of `value` in its table.
template <class E>
const char* choiceName(E value) {
  for (const ChoiceName<E>& c : Choices<E>::names)
    if (c.value == value) return c.name;
  return "?";  // not reached: every value is in its table
}

// The value named `name`, or nothing.
template <class E>
std::optional<E> parseChoice(std::string_view name) {
  for (const ChoiceName<E>& c : Choices<E>::names)
    if (name == c.name) return c.value;
  return std::nullopt;
}

// Every name, in table order (for CLI11's IsMember).
template <class E>
std::vector<std::string> choiceNames() {
  std::vector<std::string> out;
  for (const ChoiceName<E>& c : Choices<E>::names) out.emplace_back(c.name);
  return out;
}

// "a | b | c" (or with another separator).
template <class E>
std::string choiceList(std::string_view separator = " | ") {
  std::string out;
  for (const ChoiceName<E>& c : Choices<E>::names)
    out += (out.empty() ? "" : std::string(separator)) + c.name;
  return out;
}

}  // namespace meso
