// The film's channels (see film_layout.h).
#include "meso/render/film_layout.h"

#include "meso/core/error.h"

namespace meso {

Image FilmLayout::make(int width, int height) {
  return Image(width, height, std::vector<std::string>(kNames.begin(), kNames.end()));
}

Image FilmLayout::fromExr(const Image& image, const std::string& what) {
  int source[kChannels];
  bool ok = image.numChannels() == kChannels;
  for (int c = 0; c < kChannels; ++c) ok = ok && (source[c] = image.channelIndex(kNames[c])) >= 0;
  if (!ok) {
    // append() rather than operator+ chains: GCC 12 warns falsely (-Wrestrict) on the latter.
    std::string expected, found;
    for (const char* name : kNames)
      (expected.empty() ? expected : expected.append(",")).append(name);
    for (const std::string& name : image.channels)
      (found.empty() ? found : found.append(",")).append(name);
    std::string message = what;
    message.append(": not a meso film: expected the channels ").append(expected);
    throw Error(message.append(", found ").append(found.empty() ? "none" : found));
  }
  Image film = make(image.width, image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < kChannels; ++c) film.at(x, y, c) = image.at(x, y, source[c]);
  return film;
}

}  // namespace meso
