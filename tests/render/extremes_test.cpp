// Sweeps to the extremes (STYLE.md): every renderer gives a finite image, or a meso::Error, for
// grazing and overhead views, cameras touching or far from the surface, eps = 0, D = 0, zero and
// very tall relief, uv poles, zero-area faces and non-manifold meshes; T(d, theta_V) and the blend
// weights of Becker & Max 1993, eq. (10), are continuous (Lipschitz on every sampled interval).
#include "meso/core/error.h"
#include "meso/render/film_layout.h"
#include "meso/render/integrator.h"
#include "meso/render/transition.h"
#include "meso/scene/mesh_io.h"
#include "support/plane_scene.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace meso {
namespace {

namespace fs = std::filesystem;

constexpr const char* kAlgorithms[] = {"auto", "bump", "redistribution", "brdf", "displacement"};
constexpr double kDegree = std::numbers::pi / 180.0;

// A 2 x 2 plane in z = 0 (the scene scale is 2 units), uv over [0, 1]^2.
const char* kPlaneObj =
    "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 "
    "0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n";

// A UV sphere of radius 1 (rings x segments quads) whose top row is degenerate: its quads end in
// `segments` copies of the north pole, so P_u = 0 and P_u x P_v = 0 along the top. The south pole
// is a triangle fan to one vertex with face-varying uvs (again P_u x P_v = 0 at the pole).
std::string uvSphereObj(int rings, int segments) {
  std::ostringstream o;
  // Vertices: south pole (1), rings-1 latitude rings of `segments`, then `segments` north poles.
  o << "v 0 0 -1\n";
  for (int r = 1; r < rings; ++r) {
    const double theta = std::numbers::pi * r / rings - std::numbers::pi / 2;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2.0 * std::numbers::pi * s / segments;
      o << "v " << std::cos(theta) * std::cos(phi) << " " << std::cos(theta) * std::sin(phi) << " "
        << std::sin(theta) << "\n";
    }
  }
  for (int s = 0; s < segments; ++s) o << "v 0 0 1\n";
  // Texture coordinates: (s / segments, r / rings) on a (segments + 1) x (rings + 1) grid.
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s <= segments; ++s)
      o << "vt " << double(s) / segments << " " << double(r) / rings << "\n";
  const auto vtx = [&](int r,
                       int s) {  // 1-based vertex index of ring r (1..rings-1), segment s
    return 2 + (r - 1) * segments + (s % segments);
  };
  const auto tex = [&](int r, int s) { return 1 + r * (segments + 1) + s; };
  const int northBase = 2 + (rings - 1) * segments;
  for (int s = 0; s < segments; ++s)  // south fan, counter-clockwise seen from outside
    o << "f 1/" << tex(0, s) << " " << vtx(1, s + 1) << "/" << tex(1, s + 1) << " " << vtx(1, s)
      << "/" << tex(1, s) << "\n";
  for (int r = 1; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s)
      o << "f " << vtx(r, s) << "/" << tex(r, s) << " " << vtx(r, s + 1) << "/" << tex(r, s + 1)
        << " " << vtx(r + 1, s + 1) << "/" << tex(r + 1, s + 1) << " " << vtx(r + 1, s) << "/"
        << tex(r + 1, s) << "\n";
  for (int s = 0; s < segments; ++s)  // degenerate top row: quads onto distinct copies of the pole
    o << "f " << vtx(rings - 1, s) << "/" << tex(rings - 1, s) << " " << vtx(rings - 1, s + 1)
      << "/" << tex(rings - 1, s + 1) << " " << northBase + (s + 1) % segments << "/"
      << tex(rings, s + 1) << " " << northBase + s << "/" << tex(rings, s) << "\n";
  return o.str();
}

// Two unit quads and, between them, faces of zero area: a quad collapsed onto a line (distinct,
// collinear vertices) and a triangle with two coincident vertices.
const char* kZeroAreaObj =
    "v -1 -1 0\nv 0 -1 0\nv 0 1 0\nv -1 1 0\nv 1 -1 0\nv 1 1 0\n"
    "v 2 0 0\nv 3 0 0\nv 4 0 0\nv 5 0 0\nv 1 1 0\n"
    "vt 0 0\nvt 0.5 0\nvt 0.5 1\nvt 0 1\nvt 1 0\nvt 1 1\n"
    "f 1/1 2/2 3/3 4/4\nf 2/2 5/5 6/6 3/3\nf 7/1 8/2 9/5 10/6\nf 6/6 11/6 "
    "5/5\n";

// Three quads sharing the edge (0,0,0)-(0,1,0): a non-manifold "book" of three pages.
const char* kNonManifoldObj =
    "v 0 0 0\nv 0 1 0\nv 1 0 0\nv 1 1 0\nv -1 0 0\nv -1 1 0\nv 0 0 1\nv 0 1 1\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "f 1/1 3/2 4/3 2/4\nf 2/4 6/3 5/2 1/1\nf 1/1 2/2 8/3 7/4\n";

class ExtremesTest : public meso::testing::TempDirTest {
 protected:
  static fs::path cacheDir() {
    return testing::ProcessTemporaries::add(fs::temp_directory_path() /
                                            ("meso_extremes_cache_" + std::to_string(::getpid())));
  }
  static void TearDownTestSuite() { fs::remove_all(cacheDir()); }

  // A diffuse-and-specular plane with one noise relief level, seen from 3 units at 45 degrees.
  // Small appearance tables keep the whole sweep fast (they are cached per process).
  Scene scene(const std::string& algorithm, const std::string& obj = kPlaneObj,
              SubdivisionScheme scheme = SubdivisionScheme::Bilinear) const {
    Scene s;
    s.camera.position = {0.0f, -2.1f, 2.1f};
    s.camera.lookAt = {0.0f, 0.0f, 0.0f};
    s.camera.up = {0.0f, 0.0f, 1.0f};
    s.camera.width = 32;
    s.camera.height = 24;
    s.camera.fovY = 50.0f;
    s.camera.spp = 4;
    Light l;
    l.direction = glm::normalize(Vec3(0.2f, 0.7f, -0.6f));
    s.lights = {l};
    Material m;
    m.kd = Vec3(0.8f);
    m.ks = Vec3(0.2f);
    ReliefLevelDecl d;
    d.source = ReliefSource::Noise;
    d.octaves = 2;
    d.amplitude = 0.01f;
    d.scale = 4.0f;
    m.relief = {d};
    s.materials = {m};
    Object o;
    o.mesh = write("mesh.obj", obj);
    o.scheme = scheme;
    s.objects = {o};
    s.render.algorithm = *parseChoice<Algorithm>(algorithm);
    s.render.cacheDir = cacheDir();
    s.render.tessellationRate = 0;  // by view: the renderers that displace nothing, too
    s.render.dicingRate = 2.0f;
    s.render.maxMicropolygons = 200000;
    TableResolution& t = s.render.tables;
    t.thetaVBins = 4;
    t.thetaNBins = 16;
    t.phiBins = 8;
    t.azimuths = 4;
    t.raysPerView = 64;
    t.meshResolution = 16;
    t.brdfThetaL = 4;
    t.brdfPhi = 4;
    return s;
  }

  // Renders; a meso::Error is an acceptable answer (returns -1), anything else fails the test. A
  // rendered image must be finite and must not have tripped the renderer's own NaN/Inf check.
  // Returns the number of pixels that saw a surface.
  static int renderFiniteOrError(const Scene& s, const std::string& what) {
    try {
      PrepareTimes times;
      const RenderContext ctx = prepareRenderContext(s, times);
      RenderCounters counters;
      const Image img = renderFrame(ctx, RenderOptions{s.camera.spp, 7, false}, counters);
      EXPECT_EQ(img.width, s.camera.width) << what;
      EXPECT_TRUE(img.allFinite()) << what;
      EXPECT_EQ(counters.nonFinite.load(), 0) << what << ": the renderer's NaN/Inf check fired";
      int hits = 0;
      for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) hits += img.at(x, y, FilmLayout::DepthZ) > 0.0f;
      if (std::getenv("MESO_DEBUG_EXTREMES"))
        std::fprintf(stderr, "%s: %d hits\n", what.c_str(), hits);
      return hits;
    } catch (const Error& e) {
      EXPECT_FALSE(std::string(e.what()).empty()) << what;
      if (std::getenv("MESO_DEBUG_EXTREMES"))
        std::fprintf(stderr, "%s: %s\n", what.c_str(), e.what());
      return -1;
    } catch (const std::exception& e) {
      ADD_FAILURE() << what << ": not a meso::Error: " << e.what();
      return -1;
    }
  }

  // Every algorithm on the scene `edit` makes; returns how many rendered (rather than threw) with
  // at least `minHits` pixels seeing a surface.
  int sweep(int minHits, const std::string& name, const std::function<void(Scene&)>& edit,
            const std::string& obj = kPlaneObj,
            SubdivisionScheme scheme = SubdivisionScheme::Bilinear) const {
    int rendered = 0;
    for (const char* algorithm : kAlgorithms) {
      Scene s = scene(algorithm, obj, scheme);
      edit(s);
      const int hits = renderFiniteOrError(s, name + " / " + algorithm);
      if (hits >= 0) {
        EXPECT_GE(hits, minHits) << name << " / " << algorithm << ": the surface must be in view";
      }
      rendered += hits >= minHits;
    }
    return rendered;
  }
};

// theta_V = 0 (straight down), 89.9 degrees and exactly 90 degrees (the camera in the plane), at
// the default eps and at eps = 0, where T saturates at the silhouette.
TEST_F(ExtremesTest, ViewAnglesFromOverheadToInThePlane) {
  for (float eps : {0.1f, 0.0f})
    for (double thetaDeg : {0.0, 45.0, 89.9, 90.0}) {
      const auto edit = [&](Scene& s) {
        const float r = 3.0f, t = static_cast<float>(thetaDeg * kDegree);
        // Exactly 90: z = 0 exactly (cos(pi/2) in float is not 0).
        const float z = thetaDeg == 90.0 ? 0.0f : r * std::cos(t);
        s.camera.position = {0.0f, -r * std::sin(t), z};
        s.camera.up = thetaDeg == 0.0 ? Vec3(0.0f, 1.0f, 0.0f) : Vec3(0.0f, 0.0f, 1.0f);
        s.render.transition.eps = eps;
      };
      EXPECT_EQ(sweep(thetaDeg < 60.0 ? 200 : (thetaDeg < 90.0 ? 1 : 0),
                      "theta_V " + std::to_string(thetaDeg) + " eps " + std::to_string(eps), edit),
                5);
    }
}

// The light from overhead to exactly in the plane, a little below it and straight below, with and
// without shadows: the BRDF tables go on to theta_L = 180 degrees, and a light below the mean plane
// is looked up there (without shadows) or dropped (with them).
TEST_F(ExtremesTest, LightAnglesFromOverheadToStraightBelow) {
  for (bool shadows : {false, true})
    for (double thetaDeg : {0.0, 89.9, 90.0, 100.0, 180.0}) {
      const auto edit = [&](Scene& s) {
        const float t = static_cast<float>(thetaDeg * kDegree);
        // Exactly 90 and 180: the light's z is exactly 0 and -1 (cos in float is not).
        const float z = thetaDeg == 90.0 ? 0.0f : thetaDeg == 180.0 ? -1.0f : std::cos(t);
        const float y = thetaDeg == 180.0 ? 0.0f : std::sin(t);
        s.lights[0].direction = -glm::normalize(Vec3(0.0f, y, z));  // travelling away from L
        s.render.shadows = shadows;
      };
      EXPECT_EQ(
          sweep(200, "theta_L " + std::to_string(thetaDeg) + (shadows ? " shadows" : ""), edit), 5);
    }
}

// The camera 1e-6 and 1e9 times the scene scale (2 units) from the plane, overhead and oblique; far
// away both with the default field of view (the plane is far below a pixel) and with one so narrow
// that the plane fills the image again (ray origins ~1e9: float rounding of the hits and T far
// below e1).
TEST_F(ExtremesTest, CameraNearlyTouchingAndVeryFar) {
  for (double factor : {1e-6, 1e9})
    for (bool overhead : {true, false})
      for (bool narrow : {false, true}) {
        if (narrow && factor < 1.0) continue;
        const float d = static_cast<float>(2.0 * factor);
        const auto edit = [&](Scene& s) {
          s.camera.position =
              overhead ? Vec3(0.1f, 0.2f, d) : Vec3(0.1f, 0.2f - d * 0.7071f, d * 0.7071f);
          s.camera.lookAt = {0.1f, 0.2f, 0.0f};
          s.camera.up = overhead ? Vec3(0.0f, 1.0f, 0.0f) : Vec3(0.0f, 0.0f, 1.0f);
          if (narrow) s.camera.fovY = static_cast<float>(2.0 * std::atan(0.8 / d) / kDegree);
          // Nearly touching: the relief (0.01) would hold the camera inside it, above or below the
          // displaced surface depending on how finely it is diced; keep it below the camera.
          if (factor < 1.0) s.materials[0].relief[0].amplitude = 0.25f * d;
        };
        // Oblique at 1e9 the float ray directions (relative error ~6e-8 rad) cannot aim within the
        // 4e-10 rad the plane subtends, so only finiteness is asked there.
        const int minHits = factor < 1.0 ? 700 : (narrow && overhead ? 100 : 0);
        EXPECT_EQ(sweep(minHits,
                        "distance x" + std::to_string(factor) +
                            (overhead ? " overhead" : " oblique") + (narrow ? " narrow" : ""),
                        edit),
                  5);
      }
}

// eps = 0 and D = 0 over the whole range of views in one image (grazing to steep), and both at
// once.
TEST_F(ExtremesTest, ZeroEpsAndZeroD) {
  struct Knobs {
    float D, eps;
  };
  for (Knobs k : {Knobs{0.0f, 0.1f}, Knobs{2.0f, 0.0f}, Knobs{0.0f, 0.0f}}) {
    const auto edit = [&](Scene& s) {
      s.camera.position = {0.0f, -1.2f, 0.25f};
      s.camera.lookAt = {0.0f, 0.3f, 0.0f};
      s.camera.fovY = 80.0f;
      s.render.transition.D = k.D;
      s.render.transition.eps = k.eps;
    };
    EXPECT_EQ(sweep(300, "D " + std::to_string(k.D) + " eps " + std::to_string(k.eps), edit), 5);
  }
}

// Zero amplitude, a tiny one, and relief much taller than its shortest wavelength (the noise at
// scale 4 with 2 octaves has wavelengths of 1/4 and 1/8 unit; amplitude 2 is 16 of them).
TEST_F(ExtremesTest, ZeroAndVeryTallRelief) {
  for (float amplitude : {0.0f, 1e-12f, 2.0f}) {
    const auto edit = [&](Scene& s) { s.materials[0].relief[0].amplitude = amplitude; };
    EXPECT_EQ(sweep(200, "amplitude " + std::to_string(amplitude), edit), 5);
  }
  // Tall relief seen from close and grazing, where displacement and auto raise it as geometry.
  const auto close = [](Scene& s) {
    s.materials[0].relief[0].amplitude = 2.0f;
    s.camera.position = {0.0f, -0.5f, 0.2f};
  };
  EXPECT_EQ(sweep(500, "tall relief, close", close), 5);
}

// A Catmull-Clark sphere whose uv map has poles (P_u x P_v = 0), from outside and from above a
// pole: every algorithm renders it and sees it.
TEST_F(ExtremesTest, UvPolesOfACatmullClarkSphere) {
  const std::string obj = uvSphereObj(8, 12);
  EXPECT_EQ(loadControlMesh(write("sphere.obj", obj)).faceSizes.size(), 8u * 12u)
      << "no face dropped";
  for (bool abovePole : {false, true}) {
    const auto edit = [&](Scene& s) {
      s.camera.position = abovePole ? Vec3(0.0f, 0.0f, 3.0f) : Vec3(0.0f, -3.0f, 1.0f);
      s.camera.up = abovePole ? Vec3(0.0f, 1.0f, 0.0f) : Vec3(0.0f, 0.0f, 1.0f);
      s.camera.fovY = abovePole ? 20.0f : 50.0f;
      s.materials[0].relief[0].amplitude = 0.02f;
    };
    EXPECT_EQ(sweep(150, std::string("uv sphere") + (abovePole ? ", above the pole" : ""), edit,
                    obj, SubdivisionScheme::CatmullClark),
              5);
  }
}

// Zero-area faces (collinear vertices, coincident vertices), with each scheme that accepts them:
// every algorithm renders them (none refuses the mesh) and sees them.
TEST_F(ExtremesTest, ZeroAreaFaces) {
  const auto edit = [](Scene& s) {
    s.camera.position = {1.5f, -3.0f, 3.0f};
    s.camera.lookAt = {1.5f, 0.0f, 0.0f};
  };
  for (SubdivisionScheme scheme : {SubdivisionScheme::Bilinear, SubdivisionScheme::CatmullClark})
    EXPECT_EQ(sweep(100, "zero-area faces", edit, kZeroAreaObj, scheme), 5);
}

// Three quads sharing one edge: all three are kept (OpenMesh splits the complex edge by duplicating
// vertices) and every algorithm renders them finitely.
TEST_F(ExtremesTest, NonManifoldMesh) {
  EXPECT_EQ(loadControlMesh(write("book.obj", kNonManifoldObj)).faceSizes.size(), 3u);
  const auto edit = [](Scene& s) {
    s.camera.position = {0.5f, -3.0f, 2.0f};
    s.camera.lookAt = {0.0f, 0.5f, 0.3f};
  };
  for (SubdivisionScheme scheme : {SubdivisionScheme::Bilinear, SubdivisionScheme::CatmullClark})
    EXPECT_EQ(sweep(50, "non-manifold", edit, kNonManifoldObj, scheme), 5);
}

// Thresholds out of order (or on the wrong side of 0) are a clear meso::Error naming the setting.
TEST(TransitionSettingsExtremes, ThresholdsInTheWrongOrderAreAnError) {
  struct Bad {
    float e1, e2, e3, e4;
  };
  for (Bad b :
       {Bad{-0.3f, -1.0f, 0.3f, 1.0f}, Bad{-1.0f, -0.3f, 1.0f, 0.3f}, Bad{1.0f, 0.3f, -0.3f, -1.0f},
        Bad{-1.0f, -1.0f, 0.3f, 1.0f}, Bad{-1.0f, 0.0f, 0.3f, 1.0f}, Bad{-1.0f, -0.3f, 0.0f, 1.0f},
        Bad{-1.0f, 0.2f, 0.3f, 1.0f}}) {
    TransitionSettings s;
    s.e1 = b.e1, s.e2 = b.e2, s.e3 = b.e3, s.e4 = b.e4;
    try {
      validateTransitionSettings(s, "render.thresholds");
      ADD_FAILURE() << "accepted " << b.e1 << ", " << b.e2 << ", " << b.e3 << ", " << b.e4;
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("render.thresholds"), std::string::npos) << what;
      EXPECT_NE(what.find("e1 < e2 < 0 < e3 < e4"), std::string::npos) << what;
    }
  }
  TransitionSettings ok;
  EXPECT_NO_THROW(validateTransitionSettings(ok, "render.thresholds"));
  ok.D = 0.0f;
  ok.eps = 0.0f;
  EXPECT_NO_THROW(validateTransitionSettings(ok, "render.thresholds"))
      << "D = 0 and eps = 0 are allowed";
  for (float bad : {NAN, INFINITY, -1.0f}) {
    TransitionSettings s;
    s.eps = bad;
    EXPECT_THROW(validateTransitionSettings(s, "x"), Error) << bad;
  }
}

// The chain rule bound of the weights: the smoothstep ramp's slope is at most 1.5 / (b - a).
float weightSlope(const TransitionSettings& s) {
  return 1.5f * std::max(1.0f / (s.e2 - s.e1), 1.0f / (s.e4 - s.e3));
}

void expectWeightsSane(const TransitionWeights& w, const std::string& where) {
  for (float v : {w.brdf, w.redistribution, w.disp}) {
    EXPECT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f) << where << ": " << v;
  }
  EXPECT_NEAR(w.brdf + w.redistribution, 1.0f, 1e-6f) << where;
}

// |a - b| <= bound, with float rounding of values of size |a| allowed for.
bool within(float a, float b, double bound) {
  return std::abs(double(a) - double(b)) <=
         bound * 1.001 + 4e-6 * std::max({1.0, std::abs(double(a)), std::abs(double(b))});
}

// T(d) on a fine grid from d = 0 (camera on the surface) to far away, for several views and
// settings: every jump between neighbours is below the local Lipschitz bound lambda p / (d^2 (cos
// theta_V + eps)) times the step (nu saturates at 1e6, which caps d^-2).
TEST(TransitionContinuity, ContinuousInDistance) {
  const float wavelength = 0.125f, ppr = 500.0f, lp = wavelength * ppr;
  for (float eps : {0.1f, 0.01f})
    for (float D : {0.0f, 2.0f})
      for (double thetaDeg : {0.0, 60.0, 89.9, 90.0}) {
        TransitionSettings s;
        s.D = D;
        s.eps = eps;
        const float c = static_cast<float>(std::cos(thetaDeg * kDegree));
        const float cc = std::clamp(c, 0.0f, 1.0f);
        // Geometric grid with a linear start: steps of 1e-6 at the bottom, 0.1% further out.
        std::vector<float> ds = {0.0f};
        for (float d = 1e-6f; d < 1e4f; d = std::max(d * 1.001f, d + 1e-6f)) ds.push_back(d);
        float prevT = transitionParameter(wavelength, ppr, ds[0], c, s);
        TransitionWeights prevW = transitionWeights(prevT, s);
        for (size_t i = 1; i < ds.size(); ++i) {
          const float T = transitionParameter(wavelength, ppr, ds[i], c, s);
          ASSERT_TRUE(std::isfinite(T)) << ds[i];
          const TransitionWeights w = transitionWeights(T, s);
          expectWeightsSane(w, "d " + std::to_string(ds[i]));
          const double h = double(ds[i]) - double(ds[i - 1]);
          const double dEff = std::max(double(ds[i - 1]), double(lp) / 1e6);
          const double lipT = lp / (dEff * dEff * (cc + eps));
          ASSERT_TRUE(within(T, prevT, lipT * h))
              << "T jumps from " << prevT << " to " << T << " between d = " << ds[i - 1] << " and "
              << ds[i] << " (theta_V " << thetaDeg << ", eps " << eps << ", D " << D << ")";
          const double lipW = weightSlope(s) * std::abs(double(T) - double(prevT));
          ASSERT_TRUE(within(w.brdf, prevW.brdf, lipW) && within(w.disp, prevW.disp, lipW))
              << "weights jump at d = " << ds[i];
          prevT = T;
          prevW = w;
        }
      }
}

// T(theta_V) on a fine grid over [0, 90] degrees and a little beyond (cos < 0 clamps to 0): jumps
// below |nu - D| sin(theta) / (cos(theta) + eps)^2 times the step (the derivative is increasing in
// theta on [0, 90], so its value at the step's upper end bounds it).
TEST(TransitionContinuity, ContinuousInViewAngle) {
  const float wavelength = 0.125f, ppr = 500.0f;
  for (float eps : {0.1f, 0.02f})
    for (float distance : {0.5f, 31.25f, 200.0f, 1e5f}) {  // nu = 125, 2 (= D), 0.3125, ~0
      TransitionSettings s;
      s.eps = eps;
      const int n = 200000;
      const double top = 90.5 * kDegree;
      const double num = std::abs(double(wavelength * ppr / distance) - s.D);
      float prevT = transitionParameter(wavelength, ppr, distance, 1.0f, s);
      TransitionWeights prevW = transitionWeights(prevT, s);
      for (int i = 1; i <= n; ++i) {
        const double th0 = top * (i - 1) / n, th1 = top * i / n;
        const float T =
            transitionParameter(wavelength, ppr, distance, static_cast<float>(std::cos(th1)), s);
        ASSERT_TRUE(std::isfinite(T));
        const TransitionWeights w = transitionWeights(T, s);
        const double c1 = std::max(0.0, std::cos(std::min(th1, std::numbers::pi / 2)));
        const double lipT =
            num * std::sin(std::min(th1, std::numbers::pi / 2)) / ((c1 + eps) * (c1 + eps));
        // Float cos near 90 degrees has an absolute error of ~4e-8: allow it through dT/dcos.
        const double cosSlack = num * 1e-7 / ((c1 + eps) * (c1 + eps));
        ASSERT_TRUE(within(T, prevT, lipT * (th1 - th0) + cosSlack))
            << "T jumps from " << prevT << " to " << T << " at theta_V " << th1 / kDegree
            << " (eps " << eps << ", d " << distance << ")";
        const double lipW = weightSlope(s) * std::abs(double(T) - double(prevT));
        ASSERT_TRUE(within(w.brdf, prevW.brdf, lipW) && within(w.disp, prevW.disp, lipW));
        expectWeightsSane(w, "theta " + std::to_string(th1 / kDegree));
        prevT = T;
        prevW = w;
      }
    }
}

// eps = 0: T saturates at +-1e6 (or is 0 when nu = D) as theta_V -> 90 and equals that limit at 90
// exactly, so it is continuous there too; the weights stay in [0, 1].
TEST(TransitionContinuity, ZeroEpsSaturatesContinuouslyAtTheSilhouette) {
  TransitionSettings s;
  s.eps = 0.0f;
  const float wavelength = 0.125f, ppr = 500.0f;
  for (float distance : {0.5f, 31.25f, 1e5f}) {
    const float at90 = transitionParameter(wavelength, ppr, distance, 0.0f, s);
    const float beyond = transitionParameter(wavelength, ppr, distance, -0.5f, s);
    EXPECT_TRUE(std::isfinite(at90));
    EXPECT_EQ(at90, beyond) << "cos theta_V < 0 clamps to 0";
    const float nearly = transitionParameter(wavelength, ppr, distance, 1e-9f, s);
    EXPECT_TRUE(within(nearly, at90, 0.0)) << distance << ": " << nearly << " vs " << at90;
    expectWeightsSane(transitionWeights(at90, s), "eps 0, d " + std::to_string(distance));
  }
  // The weights are Lipschitz in T over [-3, 3], which holds every threshold.
  float prev = -3.0f;
  TransitionWeights prevW = transitionWeights(prev, s);
  for (int i = 1; i <= 60000; ++i) {
    const float T = -3.0f + 1e-4f * i;
    const TransitionWeights w = transitionWeights(T, s);
    expectWeightsSane(w, "T " + std::to_string(T));
    const double lipW = weightSlope(s) * (double(T) - double(prev));
    ASSERT_TRUE(within(w.brdf, prevW.brdf, lipW) && within(w.disp, prevW.disp, lipW)) << T;
    prev = T;
    prevW = w;
  }
}

}  // namespace
}  // namespace meso
