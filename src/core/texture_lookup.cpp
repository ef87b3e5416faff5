// Colour images through OpenImageIO's TextureSystem (texture_lookup.h).
#include "meso/core/texture_lookup.h"

#include "meso/core/error.h"
#include "meso/core/hash.h"
#include "meso/core/memory_budget.h"

#include <fmt/format.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/texture.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <system_error>
#include <unistd.h>
#include <vector>

namespace meso {

struct TextureLookup::Impl {
  OIIO::TextureSystem* system = nullptr;
  std::vector<OIIO::TextureSystem::TextureHandle*> handles;
  // Per texture: its one colour when every texel has it (looked up without filtering, so a
  // constant image gives exactly the constant kd or ks it stands for: filter weights that sum to
  // one only up to rounding moved 15% of a test image's pixels by 1e-7).
  std::vector<std::optional<Vec3>> constants;
};

// The process's shared TextureSystem, never destroyed: OpenImageIO 2.4's TextureSystem::destroy
// frees a private instance through its base class with the base's size (AddressSanitizer:
// new-delete-type-mismatch). The shared one lives until exit and keeps its files' handles.
TextureLookup::TextureLookup() : impl_(std::make_unique<Impl>()) {
  impl_->system = OIIO::TextureSystem::create(true);
}

TextureLookup::~TextureLookup() = default;

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool isSrgb(const OIIO::ImageSpec& spec, ColourSpace space) {
  if (space != ColourSpace::Auto) return space == ColourSpace::Srgb;
  const std::string declared = lower(spec.get_string_attribute("oiio:ColorSpace"));
  if (declared.find("srgb") != std::string::npos) return true;
  if (declared.find("linear") != std::string::npos) return false;
  return spec.format.basetype != OIIO::TypeDesc::FLOAT &&
         spec.format.basetype != OIIO::TypeDesc::HALF &&
         spec.format.basetype != OIIO::TypeDesc::DOUBLE;
}

float srgbToLinear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

uint64_t fileHash(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(in), {}};
  Hasher h;
  h.string("meso texture/1").string(bytes);
  return h.digest();
}

}  // namespace

ColourImage readColourImage(const std::filesystem::path& file, ColourSpace space, const char* what,
                            uint64_t memoryLimitBytes) {
  const std::string name = file.string();
  OIIO::ImageBuf in(name);
  if (!in.init_spec(name, 0, 0))
    throw Error(name + ": not an image OpenImageIO can read (" + in.geterror() + ")");
  const OIIO::ImageSpec& spec = in.spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw Error(name + ": the image has zero size (" + std::to_string(spec.width) + "x" +
                std::to_string(spec.height) + ", " + std::to_string(spec.nchannels) + " channels)");
  // The float pixels, their RGB copy and the mapped copy the TextureSystem gets: refused from the
  // declared size, before decoding.
  requireMemoryWithin(
      memoryLimitBytes, static_cast<double>(spec.width) * spec.height * (spec.nchannels + 6) * 4.0,
      name, what,
      "decoding " + std::to_string(spec.width) + "x" + std::to_string(spec.height) + ", " +
          std::to_string(spec.nchannels) + " channels, as the header declares");
  if (!in.read(0, 0, true, OIIO::TypeDesc::FLOAT))
    throw Error(name + ": not an image OpenImageIO can read (" + in.geterror() + ")");
  ColourImage out{Image(spec.width, spec.height, {"R", "G", "B"}), isSrgb(spec, space)};
  const int c = spec.nchannels;
  std::vector<float> texel(static_cast<size_t>(c));
  for (int y = 0; y < spec.height; ++y)
    for (int x = 0; x < spec.width; ++x) {
      in.getpixel(x + spec.x, y + spec.y, texel.data(), c);
      for (int k = 0; k < 3; ++k) {
        const float v = texel[static_cast<size_t>(c >= 3 ? k : 0)];
        if (!std::isfinite(v) || v < 0.0f)
          throw Error(name + ": texel (" + std::to_string(x) + ", " + std::to_string(y) + ") is " +
                      (std::isfinite(v) ? "negative" : "NaN or infinite") + ": " + what +
                      " hold finite values >= 0");
        out.rgb.at(x, y, k) = out.srgb ? srgbToLinear(v) : v;
      }
    }
  return out;
}

int TextureLookup::add(const std::filesystem::path& file, ColourSpace space,
                       const std::filesystem::path& folder, uint64_t memoryLimitBytes) {
  const std::string name = file.string();
  const ColourImage read = readColourImage(file, space, "colour textures", memoryLimitBytes);
  const Image& texels = read.rgb;
  const bool srgb = read.srgb;
  OIIO::ImageSpec rgbSpec(texels.width, texels.height, 3, OIIO::TypeDesc::FLOAT);
  OIIO::ImageBuf rgb(rgbSpec);
  std::optional<Vec3> constant;
  bool uniform = true;
  for (int y = 0; y < texels.height; ++y)
    for (int x = 0; x < texels.width; ++x) {
      const Vec3 value(texels.at(x, y, 0), texels.at(x, y, 1), texels.at(x, y, 2));
      rgb.setpixel(x, y, &value.x, 3);
      if (!constant) constant = value;
      uniform = uniform && value == *constant;
    }
  // The MIP-mapped copy, shared by every render of the same bytes and colour space.
  Hasher key;
  key.value(fileHash(file)).value(srgb);
  const std::string hex = fmt::format("{:016x}", key.digest());
  const std::filesystem::path tx = folder / (hex + ".tx");
  std::error_code ec;
  if (!std::filesystem::exists(tx, ec)) {
    std::filesystem::create_directories(folder, ec);
    const std::filesystem::path tmp = folder / fmt::format(".{}.{}.tx", hex, ::getpid());
    OIIO::ImageSpec config;
    config.attribute("wrapmodes", "periodic");
    config.attribute("maketx:filtername", "box");
    if (!OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, rgb, tmp.string(),
                                          config)) {
      std::filesystem::remove(tmp, ec);
      throw Error(name + ": cannot write its MIP-mapped copy " + tx.string() + " (" +
                  OIIO::geterror() + ")");
    }
    std::filesystem::rename(tmp, tx, ec);
    if (ec) {
      std::filesystem::remove(tmp, ec);
      if (!std::filesystem::exists(tx))
        throw Error(name + ": cannot write its MIP-mapped copy " + tx.string());
    }
  }
  OIIO::TextureSystem::TextureHandle* handle =
      impl_->system->get_texture_handle(OIIO::ustring(tx.string()));
  if (!handle) throw Error(name + ": the TextureSystem cannot open " + tx.string());
  impl_->handles.push_back(handle);
  impl_->constants.push_back(uniform ? constant : std::nullopt);
  return static_cast<int>(impl_->handles.size()) - 1;
}

Vec3 TextureLookup::rgb(int k, Vec2 uv, Vec2 dx, Vec2 dy) const {
  if (const std::optional<Vec3>& c = impl_->constants[static_cast<size_t>(k)]) return *c;
  OIIO::TextureOpt opt;
  opt.swrap = opt.twrap = OIIO::TextureOpt::WrapPeriodic;
  // Bilinear within a MIP level (OpenImageIO's default B-spline smooths texels under
  // magnification: a point lookup at a texel's centre would not return the texel).
  opt.interpmode = OIIO::TextureOpt::InterpBilinear;
  float out[3] = {0.0f, 0.0f, 0.0f};
  // t runs down the image: v = 1 - t.
  impl_->system->texture(impl_->handles[static_cast<size_t>(k)],
                         impl_->system->get_perthread_info(), opt, uv.x, 1.0f - uv.y, dx.x, -dx.y,
                         dy.x, -dy.y, 3, out);
  return {out[0], out[1], out[2]};
}

}  // namespace meso
