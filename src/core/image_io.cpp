// The only translation unit that includes OpenImageIO (its headers are slow to parse and its shared
// libraries slow to load: keep them out of everything else).
#include "meso/core/image_io.h"

#include "meso/core/atomic_file.h"
#include "meso/core/error.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace meso {
namespace {

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what) {
  throw Error(file.string() + ": " + what);
}

std::string oiioMessage(const std::string& primary) {
  std::string msg = primary.empty() ? OIIO::geterror() : primary;
  if (msg.empty()) msg = "unknown OpenImageIO error";
  std::replace(msg.begin(), msg.end(), '\n', ' ');
  return msg;
}

void writeWithOiio(const std::filesystem::path& tmp, const OIIO::ImageSpec& spec,
                   OIIO::TypeDesc format, const void* data) {
  auto out = OIIO::ImageOutput::create(tmp.string());
  if (!out) fail(tmp, "cannot create image writer: " + oiioMessage(""));
  if (!out->open(tmp.string(), spec)) fail(tmp, "cannot open for writing: " + oiioMessage(out->geterror()));
  if (!out->write_image(format, data)) fail(tmp, "write failed: " + oiioMessage(out->geterror()));
  if (!out->close()) fail(tmp, "close failed: " + oiioMessage(out->geterror()));
}

// IEC 61966-2-1 sRGB encoding of a linear value in [0, 1].
float srgbEncode(float v) {
  v = std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

}  // namespace

Image readImage(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) fail(file, "no such file");
  auto in = OIIO::ImageInput::open(file.string());
  if (!in) fail(file, "cannot read image: " + oiioMessage(""));
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    fail(file, "image has zero size (" + std::to_string(spec.width) + "x" +
                   std::to_string(spec.height) + ", " + std::to_string(spec.nchannels) +
                   " channels)");
  Image image(spec.width, spec.height, spec.channelnames);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data()))
    fail(file, "cannot read pixels (truncated or corrupt?): " + oiioMessage(in->geterror()));
  in->close();
  return image;
}

void writeExr(const std::filesystem::path& file, const Image& image) {
  OIIO::ImageSpec spec(image.width, image.height, image.numChannels(), OIIO::TypeDesc::FLOAT);
  spec.channelnames = image.channels;
  spec.alpha_channel = image.channelIndex("A");
  spec.attribute("compression", "zip");
  spec.attribute("Software", "meso");
  // OpenEXR otherwise stamps the current time (capDate): the same render must give the same bytes.
  spec.attribute("DateTime", "");
  writeAtomically(file, [&](const std::filesystem::path& tmp) {
    writeWithOiio(tmp, spec, OIIO::TypeDesc::FLOAT, image.pixels.data());
  });
}

void writePngPreview(const std::filesystem::path& file, const Image& image) {
  const int rgb[3] = {image.channelIndex("R"), image.channelIndex("G"), image.channelIndex("B")};
  if (rgb[0] < 0 || rgb[1] < 0 || rgb[2] < 0) fail(file, "image has no R, G, B channels");
  std::vector<uint8_t> bytes(static_cast<size_t>(image.width) * image.height * 3);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c)
        bytes[(static_cast<size_t>(y) * image.width + x) * 3 + c] =
            static_cast<uint8_t>(std::lround(255.0f * srgbEncode(image.at(x, y, rgb[c]))));
  OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:ColorSpace", "sRGB");
  writeAtomically(file, [&](const std::filesystem::path& tmp) {
    writeWithOiio(tmp, spec, OIIO::TypeDesc::UINT8, bytes.data());
  });
}

}  // namespace meso
