// The named choices of scene files: every name round-trips through its table, unknown names are
// refused (no silent default), and docs/scene-format.md lists exactly the table's names.
#include "meso/scene/choices.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

namespace {

using namespace meso;

template <class E>
void expectRoundTrip() {
  for (const ChoiceName<E>& c : Choices<E>::names) {
    ASSERT_TRUE(parseChoice<E>(c.name).has_value()) << c.name;
    EXPECT_EQ(*parseChoice<E>(c.name), c.value) << c.name;
    EXPECT_STREQ(choiceName(c.value), c.name);
  }
  EXPECT_FALSE(parseChoice<E>("").has_value());
  EXPECT_FALSE(parseChoice<E>("Auto ").has_value());
  EXPECT_FALSE(parseChoice<E>("no-such-choice").has_value());
}

TEST(Choices, EveryNameRoundTripsAndUnknownNamesAreRefused) {
  expectRoundTrip<Algorithm>();
  expectRoundTrip<ShadingNormals>();
  expectRoundTrip<RedistributionVariant>();
  expectRoundTrip<ReliefSource>();
  expectRoundTrip<NdfType>();
  expectRoundTrip<LightType>();
  expectRoundTrip<SubdivisionScheme>();
  expectRoundTrip<DicingMetric>();
  expectRoundTrip<Component>();
  expectRoundTrip<TableFormat>();
  EXPECT_EQ(parseChoice<DicingMetric>("projected"), DicingMetric::Projected);
  EXPECT_EQ(parseChoice<DicingMetric>("isotropic"), DicingMetric::Isotropic);
  EXPECT_FALSE(parseChoice<DicingMetric>("screen").has_value());
  EXPECT_EQ(choiceList<Component>(), "diffuse | specular | both");
  EXPECT_EQ(choiceList<TableFormat>(), "csv | markdown");
  EXPECT_EQ(choiceList<Algorithm>(), "auto | brdf | bump | redistribution | displacement");
  EXPECT_EQ(choiceNames<NdfType>(),
            (std::vector<std::string>{"beckmann", "blinn-phong", "tabulated", "relief"}));
}

// The allowed-values column of the n-th table row "| `key` | ..." of docs/scene-format.md.
std::string docRow(const std::string& key, int n) {
  std::ifstream in(std::string(MESO_SOURCE_DIR) + "/docs/scene-format.md");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("| `" + key + "` |", 0) == 0 && n-- == 0)
      return line.substr(key.size() + 6, line.find('|', key.size() + 6) - key.size() - 6);
  ADD_FAILURE() << "docs/scene-format.md has no row for " << key;
  return "";
}

template <class E>
void expectDocumented(const std::string& key, int n = 0) {
  const std::string row = docRow(key, n);
  size_t quoted = 0;
  for (size_t at = row.find('"'); at != std::string::npos; at = row.find('"', at + 1)) ++quoted;
  EXPECT_EQ(quoted, 2 * Choices<E>::names.size()) << row;
  for (const ChoiceName<E>& c : Choices<E>::names)
    EXPECT_NE(row.find('"' + std::string(c.name) + '"'), std::string::npos)
        << key << ": " << c.name;
}

TEST(Choices, SceneFormatDocumentsEveryName) {
  expectDocumented<Algorithm>("algorithm");
  expectDocumented<ShadingNormals>("normals");
  expectDocumented<RedistributionVariant>("variant");
  expectDocumented<LightType>("type", 0);
  expectDocumented<NdfType>("type", 1);
  expectDocumented<SubdivisionScheme>("scheme");
  expectDocumented<DicingMetric>("dicing_metric");
}

}  // namespace
