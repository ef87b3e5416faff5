// DESIGN.md section 4: heights are centred on their mean, the midlevel that stays on the surface.
#include "meso/relief/height_source.h"

namespace meso {

float HeightSource::meanHeight() const {
  constexpr int kGrid = 128;
  double sum = 0.0;
  for (int j = 0; j < kGrid; ++j)
    for (int i = 0; i < kGrid; ++i)
      sum += height(
          Vec2((static_cast<float>(i) + 0.5f) / kGrid, (static_cast<float>(j) + 0.5f) / kGrid));
  return static_cast<float>(sum / (kGrid * kGrid));
}

}  // namespace meso
