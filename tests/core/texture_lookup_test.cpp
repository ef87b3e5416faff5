// Colour textures through OpenImageIO's TextureSystem: texel orientation, filtering, colour
// spaces, constant images, bad files.
#include "meso/core/error.h"
#include "meso/core/image_io.h"
#include "meso/core/texture_lookup.h"

#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

namespace meso {
namespace {

namespace fs = std::filesystem;

class TextureLookupTest : public testing::TempDirTest {
 protected:
  // An RGB image whose texel (x, y) (y = 0 the top row) is f(x, y).
  template <typename F>
  fs::path rgbImage(const std::string& name, int w, int h, F f) const {
    Image img(w, h, {"R", "G", "B"});
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const Vec3 c = f(x, y);
        for (int k = 0; k < 3; ++k) img.at(x, y, k) = c[k];
      }
    writeExr(dir_ / name, img);
    return dir_ / name;
  }
  fs::path cache() const { return dir_ / "textures"; }
};

TEST_F(TextureLookupTest, ConstantImageIsExactlyItsColour) {
  TextureLookup t;
  const int k = t.add(rgbImage("c.exr", 8, 8, [](int, int) { return Vec3(0.5f, 0.25f, 0.1f); }),
                      ColourSpace::Auto, cache());
  for (Vec2 uv : {Vec2(0.1f, 0.7f), Vec2(-3.2f, 5.5f)})
    for (float size : {0.0f, 0.01f, 2.0f})
      EXPECT_EQ(t.rgb(k, uv, Vec2(size, 0.0f), Vec2(0.0f, size)), Vec3(0.5f, 0.25f, 0.1f));
}

// v = 0 is the image's bottom row (as for height images); point lookups at texel centres read the
// texels; (u, v) repeats.
TEST_F(TextureLookupTest, PointLookupsReadTexelsBottomRowFirst) {
  TextureLookup t;
  const auto value = [](int x, int y) {
    return Vec3(static_cast<float>(x) / 4.0f, static_cast<float>(y) / 4.0f, 0.3f);
  };
  const int k = t.add(rgbImage("g.exr", 4, 4, value), ColourSpace::Linear, cache());
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      const Vec2 uv((x + 0.5f) / 4.0f, 1.0f - (y + 0.5f) / 4.0f);
      const Vec3 c = t.rgb(k, uv, Vec2(0.0f), Vec2(0.0f));
      EXPECT_NEAR(c.x, value(x, y).x, 1e-5f) << x << " " << y;
      EXPECT_NEAR(c.y, value(x, y).y, 1e-5f) << x << " " << y;
      const Vec3 wrapped = t.rgb(k, uv + Vec2(2.0f, -1.0f), Vec2(0.0f), Vec2(0.0f));
      EXPECT_NEAR(wrapped.x, c.x, 1e-5f);
      EXPECT_NEAR(wrapped.y, c.y, 1e-5f);
    }
}

// A footprint as large as the image averages it; a small one keeps the texel.
TEST_F(TextureLookupTest, FilteredLookupsAverageTheFootprint) {
  TextureLookup t;
  const int k =
      t.add(rgbImage("checker.exr", 64, 64,
                     [](int x, int y) { return Vec3(((x / 8 + y / 8) % 2) ? 1.0f : 0.0f); }),
            ColourSpace::Linear, cache());
  const Vec2 centre(4.0f / 64.0f, 1.0f - 4.0f / 64.0f);  // inside texel block (0, 0): black
  EXPECT_NEAR(t.rgb(k, centre, Vec2(1e-3f, 0.0f), Vec2(0.0f, 1e-3f)).x, 0.0f, 1e-3f);
  EXPECT_NEAR(t.rgb(k, centre + Vec2(8.0f / 64.0f, 0.0f), Vec2(1e-3f, 0.0f), Vec2(0.0f, 1e-3f)).x,
              1.0f, 1e-3f);
  EXPECT_NEAR(t.rgb(k, centre, Vec2(1.0f, 0.0f), Vec2(0.0f, 1.0f)).x, 0.5f, 0.02f);
  // An anisotropic footprint along u averages the checks it crosses, not those across it.
  const float along =
      t.rgb(k, Vec2(0.5f, 1.0f - 4.0f / 64.0f), Vec2(0.5f, 0.0f), Vec2(0.0f, 0.002f)).x;
  EXPECT_NEAR(along, 0.5f, 0.1f);
}

// 8-bit images without a declared colour space are sRGB: their values come back linear; the
// material's colour_space overrides it.
TEST_F(TextureLookupTest, SrgbImagesAreLinearized) {
  Image img(4, 4, {"R", "G", "B"});
  for (float& v : img.pixels) v = 0.2f;  // linear; the PNG preview stores it sRGB-encoded
  writePngPreview(dir_ / "s.png", img);
  TextureLookup t;
  const int a = t.add(dir_ / "s.png", ColourSpace::Auto, cache());
  const int l = t.add(dir_ / "s.png", ColourSpace::Linear, cache());
  EXPECT_NEAR(t.rgb(a, Vec2(0.3f), Vec2(0.0f), Vec2(0.0f)).x, 0.2f, 0.004f);
  // The stored code value, 124 / 255 (0.2 encoded), read as linear.
  EXPECT_NEAR(t.rgb(l, Vec2(0.3f), Vec2(0.0f), Vec2(0.0f)).x, 0.4845f, 0.004f);
  // The MIP-mapped copies are written whole: no temporary is left in the folder.
  for (const auto& e : fs::directory_iterator(cache()))
    EXPECT_NE(e.path().filename().string()[0], '.') << e.path();
}

TEST_F(TextureLookupTest, BadImagesAreErrorsNamingTheFile) {
  const auto errorOf = [&](const fs::path& file) {
    try {
      TextureLookup t;
      t.add(file, ColourSpace::Auto, cache());
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const fs::path text = write("notes.png", "not an image\n");
  EXPECT_NE(errorOf(text).find(text.string() + ": not an image"), std::string::npos);
  EXPECT_NE(errorOf(dir_ / "missing.exr").find("missing.exr"), std::string::npos);
  const fs::path nan = rgbImage("nan.exr", 2, 2, [](int x, int) {
    return Vec3(x ? std::numeric_limits<float>::quiet_NaN() : 0.5f);
  });
  EXPECT_NE(errorOf(nan).find(nan.string() + ": texel (1, 0) is NaN or infinite"),
            std::string::npos);
  const fs::path negative =
      rgbImage("neg.exr", 2, 2, [](int, int y) { return Vec3(y ? -1.0f : 0.5f); });
  EXPECT_NE(errorOf(negative).find(negative.string() + ": texel (0, 1) is negative"),
            std::string::npos);
}

}  // namespace
}  // namespace meso
