// A floating-point image with named channels ("R", "G", "B", "depth.Z", "normal.X", ...).
#pragma once

#include "meso/core/check.h"
#include "meso/core/huge_pages.h"

#include <string>
#include <vector>

namespace meso {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::string> channels;
  std::vector<float> pixels;  // row-major, top row first, channels interleaved

  Image() = default;
  Image(int w, int h, std::vector<std::string> names)
      : width(w), height(h), channels(std::move(names)) {
    // A film of tens of MiB: its pages mapped on every core, then zeroed.
    resizePopulated(pixels, static_cast<size_t>(w) * h * channels.size());
  }

  int numChannels() const { return static_cast<int>(channels.size()); }
  float& at(int x, int y, int c) {
    MESO_DCHECK(inside(x, y, c), "pixel and channel within the image");
    return pixels[(static_cast<size_t>(y) * width + x) * channels.size() + c];
  }
  float at(int x, int y, int c) const {
    MESO_DCHECK(inside(x, y, c), "pixel and channel within the image");
    return pixels[(static_cast<size_t>(y) * width + x) * channels.size() + c];
  }
  bool inside(int x, int y, int c) const {
    return x >= 0 && x < width && y >= 0 && y < height && c >= 0 && c < numChannels();
  }
  // Index of a named channel, or -1.
  int channelIndex(const std::string& name) const {
    for (size_t i = 0; i < channels.size(); ++i)
      if (channels[i] == name) return static_cast<int>(i);
    return -1;
  }
  // True when no pixel value is NaN or Inf.
  bool allFinite() const;
};

}  // namespace meso
