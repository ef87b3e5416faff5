#include "meso/appearance/table_plots.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace meso {
namespace {

constexpr int kGap = 3;

// A perceptually ordered dark-blue -> teal -> yellow ramp (close to viridis).
Vec3 colourRamp(float t) {
  t = std::clamp(std::isfinite(t) ? t : 0.0f, 0.0f, 1.0f);
  const Vec3 stops[5] = {{0.267f, 0.005f, 0.329f},
                         {0.230f, 0.322f, 0.546f},
                         {0.128f, 0.567f, 0.551f},
                         {0.369f, 0.789f, 0.383f},
                         {0.993f, 0.906f, 0.144f}};
  const float s = t * 4.0f;
  const int i = std::min(static_cast<int>(s), 3);
  return glm::mix(stops[i], stops[i + 1], s - static_cast<float>(i));
}

// Fills panel (px, py) of a grid with a cols x rows heat map given by value(col, row) / scale.
void drawPanel(Image& img, int x0, int y0, int cols, int rows, int cell, float scale,
               const std::function<float(int, int)>& value) {
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const Vec3 colour = colourRamp(scale > 0.0f ? value(c, r) / scale : 0.0f);
      for (int y = 0; y < cell; ++y)
        for (int x = 0; x < cell; ++x)
          for (int ch = 0; ch < 3; ++ch)
            img.at(x0 + c * cell + x, y0 + r * cell + y, ch) = colour[ch];
    }
}

Image blankGrid(int panelsX, int panelsY, int panelW, int panelH) {
  Image img(panelsX * (panelW + kGap) + kGap, panelsY * (panelH + kGap) + kGap, {"R", "G", "B"});
  std::fill(img.pixels.begin(), img.pixels.end(), 1.0f);
  return img;
}

}  // namespace

Image plotHistogram(const VisibleNormalHistogram& h, int cell) {
  const HistogramResolution& r = h.resolution();
  const int perRow = std::min(r.thetaV, 4);
  const int panelRows = (r.thetaV + perRow - 1) / perRow;
  Image img = blankGrid(perRow, panelRows, r.thetaN * cell, r.phi * cell);
  for (int k = 0; k < r.thetaV; ++k) {
    // Tables with view-azimuth slices: the phi_V slice nearest 0 of each theta_V.
    const int slice = h.sliceOf(k, 0);
    const auto density = [&](int i, int j) { return h.mass(slice, i, j) / h.solidAngle(i); };
    float maxDensity = 0.0f;
    for (int i = 0; i < r.thetaN; ++i)
      for (int j = 0; j < r.phi; ++j) maxDensity = std::max(maxDensity, density(i, j));
    drawPanel(img, kGap + (k % perRow) * (r.thetaN * cell + kGap),
              kGap + (k / perRow) * (r.phi * cell + kGap), r.thetaN, r.phi, cell, maxDensity,
              density);
  }
  return img;
}

Image plotBrdf(const BrdfTable& b, int cell) {
  const BrdfResolution& r = b.resolution();
  const int n = b.numThetaV();
  Image img = blankGrid(n, 2, r.thetaL * cell, r.phi * cell);
  float maxDiff = 0.0f, maxSpec = 0.0f;
  // Tables with view-azimuth slices: the phi_V slice nearest 0, and its phi_{V-L} >= 0 half.
  const int pv = b.numPhiV(), j0 = pv > 1 ? r.phi - 1 : 0;
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < r.thetaL; ++i)
      for (int j = 0; j < r.phi; ++j) {
        maxDiff = std::max(maxDiff, b.entry(k * pv, i, j0 + j).diffuse);
        maxSpec = std::max(maxSpec, b.entry(k * pv, i, j0 + j).specular);
      }
  for (int k = 0; k < n; ++k) {
    const int x0 = kGap + k * (r.thetaL * cell + kGap);
    drawPanel(img, x0, kGap, r.thetaL, r.phi, cell, maxDiff,
              [&](int i, int j) { return b.entry(k * pv, i, j0 + j).diffuse; });
    drawPanel(img, x0, 2 * kGap + r.phi * cell, r.thetaL, r.phi, cell, maxSpec,
              [&](int i, int j) { return b.entry(k * pv, i, j0 + j).specular; });
  }
  return img;
}

}  // namespace meso
