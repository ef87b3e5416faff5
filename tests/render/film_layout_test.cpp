// The film layout: one name per channel; a film read back in another channel order (OpenEXR's) is
// put back in layout order by name, and images with other channels (missing, extra, renamed) are
// refused with their names.
#include "meso/render/film_layout.h"

#include "meso/core/error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

namespace meso {
namespace {

TEST(FilmLayout, NamesAreUniqueAndMakeUsesThem) {
  const std::set<std::string> names(FilmLayout::kNames.begin(), FilmLayout::kNames.end());
  EXPECT_EQ(names.size(), static_cast<size_t>(FilmLayout::kChannels));
  EXPECT_STREQ(FilmLayout::kNames[FilmLayout::R], "R");
  EXPECT_STREQ(FilmLayout::kNames[FilmLayout::DepthZ], "depth.Z");
  EXPECT_STREQ(FilmLayout::kNames[FilmLayout::NormalZ], "normal.Z");
  EXPECT_STREQ(FilmLayout::kNames[FilmLayout::AlgorithmB], "algorithm.B");
  EXPECT_STREQ(FilmLayout::kNames[FilmLayout::T], "T.Y");
  const Image film = FilmLayout::make(3, 2);
  EXPECT_EQ(film.width, 3);
  EXPECT_EQ(film.height, 2);
  ASSERT_EQ(film.numChannels(), FilmLayout::kChannels);
  for (int c = 0; c < FilmLayout::kChannels; ++c) {
    EXPECT_EQ(film.channels[c], FilmLayout::kNames[c]);
    EXPECT_EQ(film.channelIndex(FilmLayout::kNames[c]), c);
  }
  for (float v : film.pixels) EXPECT_EQ(v, 0.0f);
}

// Channels as OpenEXR returns them (R, G, B, then sorted by name), each pixel's value naming its
// channel: fromExr restores the layout's order.
TEST(FilmLayout, FromExrRestoresTheLayoutOrder) {
  std::vector<std::string> names(FilmLayout::kNames.begin() + 3, FilmLayout::kNames.end());
  std::sort(names.begin(), names.end());
  names.insert(names.begin(), {"R", "G", "B"});
  Image read(3, 2, names);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      for (int c = 0; c < read.numChannels(); ++c) {
        int layout = 0;
        while (FilmLayout::kNames[layout] != read.channels[c]) ++layout;
        read.at(x, y, c) = static_cast<float>(100 * layout + 10 * y + x);
      }
  ASSERT_NE(read.channels[3], "depth.Z");  // the order really differs
  const Image film = FilmLayout::fromExr(read, "read.exr");
  ASSERT_EQ(film.channels, FilmLayout::make(1, 1).channels);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      for (int c = 0; c < FilmLayout::kChannels; ++c)
        EXPECT_EQ(film.at(x, y, c), static_cast<float>(100 * c + 10 * y + x));
  const Image same = FilmLayout::fromExr(film, "film.exr");
  EXPECT_EQ(same.pixels, film.pixels);
}

TEST(FilmLayout, FromExrRefusesOtherChannels) {
  Image renamed = FilmLayout::make(2, 2);
  renamed.channels[FilmLayout::T] = "T.Z";
  EXPECT_THROW(FilmLayout::fromExr(renamed, "renamed.exr"), Error);
  Image missing(2, 2,
                std::vector<std::string>(FilmLayout::kNames.begin(), FilmLayout::kNames.end() - 1));
  EXPECT_THROW(FilmLayout::fromExr(missing, "missing.exr"), Error);
  Image extra = FilmLayout::make(2, 2);
  extra.channels.push_back("A");
  extra.pixels.resize(extra.pixels.size() / FilmLayout::kChannels * (FilmLayout::kChannels + 1));
  EXPECT_THROW(FilmLayout::fromExr(extra, "extra.exr"), Error);
  try {
    FilmLayout::fromExr(Image(1, 1, {"Y"}), "height.exr");
    ADD_FAILURE() << "an image that is not a film was accepted";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("height.exr: ", 0), 0u) << what;
    EXPECT_NE(what.find("found Y"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace meso
