// Fractal NDF synthesis in the renderer (Kautz et al. 2001 as meso's finest level): zooming in
// adds synthesized detail without changing the mean intensity, the false-colour layer shows it,
// and a Blinn-Phong NDF far away is the local model it generalizes.
#include "meso/appearance/material_tables.h"
#include "meso/render/film_layout.h"
#include "meso/render/integrator.h"
#include "meso/render/synthesis_shader.h"

#include "meso/core/rng.h"

#include "support/plane_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace meso {
namespace {

namespace fs = std::filesystem;

// A plane seen at 30 degrees from its normal from `distance`, lit so that the highlight is in view.
Scene zoomScene(const std::string& ndfType, float distance) {
  Material m;
  m.ka = Vec3(0.02f);
  m.kd = Vec3(0.3f);
  m.ks = Vec3(0.6f);
  m.phong = 30.0f;
  m.ndf.present = true;
  m.ndf.type = *parseChoice<NdfType>(ndfType);
  m.ndf.alpha = Vec2(0.25f);
  m.ndf.exponent = 30.0f;
  m.ndf.scale = 16.0f;
  m.ndf.octaves = 10;
  m.ndf.seed = 4;
  // Light near the mirror direction of V.
  Scene s = testing::planeScene(testing::writePlaneObj("synth", 100.0f, -100.0f, 100.0f), "auto", m,
                                -Vec3(0.0f, 0.35f, 0.9367f), "synth");
  const Vec3 towardsEye = glm::normalize(Vec3(0.0f, -0.5f, 0.8660254f));
  s.camera.lookAt = Vec3(0.0f);
  s.camera.position = distance * towardsEye;
  s.camera.width = 64;
  s.camera.height = 48;
  s.camera.fovY = 10.0f;
  s.camera.spp = 4;
  s.render.tessellationRate = 1;
  return s;
}

struct Means {
  double intensity = 0.0;
  double synthesis = 0.0;  // mean magenta share of the algorithm layer
};

// The surface's mean intensity at one distance: the average over small views aimed at `views`
// random points spread over many synthesized features (one view deep in a zoom sees a fraction of a
// single feature, whose own shading is not the mean).
Means meanOverSurface(const std::string& type, float distance, int views) {
  const Scene s = zoomScene(type, distance);
  PrepareTimes times;
  RenderContext ctx = prepareRenderContext(s, times);
  const Vec3 offset = s.camera.position - s.camera.lookAt;
  Rng rng(17);
  Means m;
  double n = 0.0;
  for (int k = 0; k < views; ++k) {
    CameraSettings cam = s.camera;
    cam.width = 4;
    cam.height = 4;
    cam.spp = 1;
    cam.lookAt = Vec3(40.0f * (rng.uniform() - 0.5f), 40.0f * (rng.uniform() - 0.5f), 0.0f);
    cam.position = cam.lookAt + offset;
    prepareFrame(ctx, cam, times);
    RenderCounters counters;
    const Image img = renderFrame(ctx, {cam.spp, static_cast<uint64_t>(k), false}, counters);
    EXPECT_EQ(counters.nonFinite.load(), 0);
    const int B = FilmLayout::AlgorithmB, G = FilmLayout::AlgorithmG;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        m.intensity += img.at(x, y, FilmLayout::R);
        m.synthesis += 2.0 * (img.at(x, y, B) - img.at(x, y, G));  // magenta (1, 0, 1) against grey
        n += 1.0;
      }
  }
  m.intensity /= n;
  m.synthesis = std::clamp(m.synthesis / n, 0.0, 1.0);
  return m;
}

// Beckmann slopes are Gaussian, so structure and lobe convolve back to the NDF: 1% (measured
// +0.5% at most). Blinn-Phong is not Gaussian in slope space: 2% (measured -1.4% deep in the zoom).
TEST(SynthesisRender, MeanIntensityHoldsFromFarToDeepZoom) {
  for (const char* type : {"beckmann", "blinn-phong"}) {
    const double tolerance = std::string(type) == "beckmann" ? 0.01 : 0.02;
    const float far = 8.0f;
    const Means reference = meanOverSurface(type, far, 256);
    EXPECT_LT(reference.synthesis, 0.01) << "far away: no synthesized detail";
    for (float zoom : {4.0f, 16.0f, 64.0f, 256.0f}) {
      const Means m = meanOverSurface(type, far / zoom, 4096);
      std::printf("  %s distance d/%g: mean %.4f (far %.4f, %+.2f%%), synthesis share %.2f\n", type,
                  zoom, m.intensity, reference.intensity,
                  100.0 * (m.intensity / reference.intensity - 1.0), m.synthesis);
      EXPECT_NEAR(m.intensity, reference.intensity, tolerance * reference.intensity)
          << type << " zoom " << zoom;
      if (zoom == 16.0f) {
        EXPECT_GT(m.synthesis, 0.2) << type << " zoom " << zoom;  // fading in
      }
      if (zoom >= 64.0f) {
        EXPECT_GT(m.synthesis, 0.99) << type << " zoom " << zoom;
      }
    }
  }
}

// Kautz et al. section 7 through the index texture: the finest relief level's NDF, and detail that
// starts from that level's own normals (no change before the first octave fades in), grows while
// the first octave fades in and then keeps its spread as finer octaves add finer detail.
TEST(SynthesisRender, IndexTextureContinuesTheReliefsOwnNormals) {
  Material m;
  ReliefLevelDecl d;
  d.source = ReliefSource::Noise;
  d.octaves = 3;
  d.amplitude = 0.01f;
  d.scale = 4.0f;
  m.relief = {d};
  m.ndf.present = true;
  m.ndf.type = NdfType::Relief;
  m.ndf.octaves = 8;
  const TableCache none{fs::path()};
  const MaterialRelief r = buildMaterialRelief(m, none, nullptr);
  ASSERT_TRUE(r.synthesis && r.synthesis->index);
  Rng rng(5);
  double previous = -1.0;
  for (float c : {0.0f, 0.3f, 1.0f, 3.0f}) {
    double angle = 0.0;
    for (int k = 0; k < 2000; ++k) {
      const Vec3 n = synthesizedNormal(*r.synthesis, Vec2(rng.uniform(), rng.uniform()), c);
      ASSERT_TRUE(isFinite(n));
      angle += std::acos(std::clamp(n.z, -1.0f, 1.0f));
    }
    angle = degrees(static_cast<float>(angle / 2000));
    std::printf("  octave count %.1f: mean deviation from the relief's own normal %.3f degrees\n",
                c, angle);
    if (c == 0.0f) {
      EXPECT_EQ(angle, 0.0);
    } else if (c <= 1.0f) {
      EXPECT_GT(angle, previous + 0.1);  // noise grows as the first octave fades in
    } else {
      EXPECT_NEAR(angle, previous, 0.2 * previous);  // then holds its spread (t is normalized)
    }
    previous = angle;
  }
}

// Far away (no octave in) a Blinn-Phong NDF with exponent n is the local model (H.N)^n it
// generalizes, pixel for pixel.
TEST(SynthesisRender, FarBlinnPhongNdfIsTheLocalModel) {
  Scene withNdf = zoomScene("blinn-phong", 8.0f), plain = withNdf;
  plain.materials[0].ndf.present = false;
  PrepareTimes times;
  const RenderContext a = prepareRenderContext(withNdf, times),
                      b = prepareRenderContext(plain, times);
  RenderCounters counters;
  const Image ia = renderFrame(a, {1, 1, false}, counters),
              ib = renderFrame(b, {1, 1, false}, counters);
  double worst = 0.0;
  for (size_t i = 0; i < ia.pixels.size(); i += ia.numChannels())
    worst = std::max(worst, static_cast<double>(std::abs(ia.pixels[i] - ib.pixels[i])));
  EXPECT_LT(worst, 2e-3) << "largest difference of R";
}

}  // namespace
}  // namespace meso

namespace meso {
namespace {

// The filtered bump renderer continues into the level below the finest relief: with an NDF it
// shades synthesized detail (the magenta share of the algorithm layer is > 0 up close), as auto
// does, instead of falling back to (H.N)^phong.
TEST(SynthesisRender, FilteredBumpReachesSynthesis) {
  Scene s = zoomScene("beckmann", 0.05f);
  s.materials[0].relief = {testing::noiseLevel(0.002f, 2.0f, 2)};
  s.render.algorithm = Algorithm::Bump;
  PrepareTimes times;
  const RenderContext ctx = prepareRenderContext(s, times);
  RenderCounters counters;
  const Image img = renderFrame(ctx, {s.camera.spp, 3, false}, counters);
  ASSERT_TRUE(img.allFinite());
  const int R = FilmLayout::AlgorithmR, B = FilmLayout::AlgorithmB;
  double magenta = 0.0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) magenta += std::min(img.at(x, y, R), img.at(x, y, B));
  EXPECT_GT(magenta / (img.width * img.height), 0.5) << "synthesis should show up close";
}

}  // namespace
}  // namespace meso
