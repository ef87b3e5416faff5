// Encoding a frame's outputs: the EXR (11 float channels, as `meso render` writes them) and the
// 8-bit PNG preview of a 1280x720 image made here, smooth shading with per-pixel noise as a
// Monte Carlo render has. Usage: build/tools/bench_image [--benchmark_filter=...]
#include "meso/core/image.h"
#include "meso/core/image_io.h"

#include "bench_main.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>

namespace {

meso::Image frameLike(int w, int h) {
  meso::Image img(w, h,
                  {"R", "G", "B", "T.Y", "algorithm.R", "algorithm.G", "algorithm.B", "depth.Z",
                   "normal.X", "normal.Y", "normal.Z"});
  uint32_t state = 12345u;
  const auto noise = [&state] {
    state = state * 1664525u + 1013904223u;
    return static_cast<float>(state >> 8) / 16777216.0f - 0.5f;
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float u = static_cast<float>(x) / w, v = static_cast<float>(y) / h;
      const float shade = 0.3f + 0.2f * std::sin(40.0f * u) * std::cos(25.0f * v) + 0.05f * noise();
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = shade * (0.8f + 0.1f * c);
      img.at(x, y, 3) = v;
      img.at(x, y, 4 + (x * 3 / w)) = 1.0f;
      img.at(x, y, 7) = 1.0f / (0.05f + v);
      img.at(x, y, 8) = 0.1f * noise();
      img.at(x, y, 9) = 1.0f;
      img.at(x, y, 10) = 0.1f * noise();
    }
  return img;
}

void BM_EncodeExr(benchmark::State& state) {
  const meso::Image img = frameLike(1280, 720);
  for (auto _ : state) benchmark::DoNotOptimize(meso::encodeExr(img));
  state.counters["MB"] = static_cast<double>(meso::encodeExr(img).size()) / 1e6;
}
BENCHMARK(BM_EncodeExr)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_EncodePngPreview(benchmark::State& state) {
  const meso::Image img = frameLike(1280, 720);
  for (auto _ : state) benchmark::DoNotOptimize(meso::encodePngPreview(img));
  state.counters["MB"] = static_cast<double>(meso::encodePngPreview(img).size()) / 1e6;
}
BENCHMARK(BM_EncodePngPreview)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

MESO_BENCHMARK_MAIN()
