// The film renderFrame writes, stated once (as pbrt-v4's film.h): which channel holds which layer,
// and its EXR name. The integrator writes these channels and every consumer (the trade study, the
// consistency study, tests) reads them by index, never by name.
#pragma once

#include "meso/core/image.h"

#include <array>
#include <string>

namespace meso {

struct FilmLayout {
  // Channel indices, in file order.
  enum Channel : int {
    R,  // beauty (or the algorithm colours with --false-colour)
    G,
    B,
    DepthZ,   // mean distance from the eye over the samples that hit a surface, 0 where none did
    NormalX,  // mean world-space shading normal over hits (facing the eye), 0 where none did
    NormalY,
    NormalZ,
    AlgorithmR,  // the renderer colours of DESIGN.md section 2 mixed by blend weights, averaged
    AlgorithmG,  // over all samples
    AlgorithmB,
    T,  // mean transition parameter of the finest visible level over hits
  };
  static constexpr int kChannels = T + 1;
  // The EXR channel names, by Channel.
  static constexpr std::array<const char*, kChannels> kNames{
      "R",        "G",           "B",           "depth.Z",     "normal.X", "normal.Y",
      "normal.Z", "algorithm.R", "algorithm.G", "algorithm.B", "T.Y"};

  // A film of this layout, every value 0.
  static Image make(int width, int height);
  // A film read back from an EXR that meso wrote. OpenEXR keeps channels in an order of its own
  // (R, G, B first, the others sorted by name), so they are matched to the layout by name, once,
  // here. Throws meso::Error("<what>: ...") unless `image` has exactly these channels.
  static Image fromExr(const Image& image, const std::string& what);
};

}  // namespace meso
