// The only translation unit that includes OpenImageIO (its headers are slow to parse and its shared
// libraries slow to load: keep them out of everything else).
#include "meso/core/image_io.h"

#include "meso/core/atomic_file.h"
#include "meso/core/error.h"
#include "meso/core/image_io_memory.h"
#include "meso/core/input_file.h"
#include "meso/core/memory_budget.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

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

// Random access to the bytes of an image: up to `count` bytes from `offset` (fewer at the end).
using ByteReader = std::function<std::string(uint64_t offset, size_t count)>;

uint32_t bigEndian32(const std::string& b, size_t at) {
  return (uint32_t(uint8_t(b[at])) << 24) | (uint32_t(uint8_t(b[at + 1])) << 16) |
         (uint32_t(uint8_t(b[at + 2])) << 8) | uint32_t(uint8_t(b[at + 3]));
}

std::string printable(std::string s) {
  for (char& c : s)
    if (c < 32 || c > 126) c = '?';
  return s;
}

// The bytes OpenEXR reads for a value of `type` whose header declares `declared` bytes at
// `valueAt`: the fixed size of a fixed-size type, the parsed length of a channel list (UINT64_MAX
// when it does not end within `declared`), and `declared` for the others (strings, vectors, opaque
// types), which OpenEXR reads by the declared size.
uint64_t exrValueSize(const std::string& type, const ByteReader& read, uint64_t valueAt,
                      uint64_t declared) {
  static const std::map<std::string, uint64_t> kFixed = {
      {"box2i", 16},      {"box2f", 16},   {"chromaticities", 32},
      {"compression", 1}, {"double", 8},   {"envmap", 1},
      {"float", 4},       {"int", 4},      {"keycode", 28},
      {"lineOrder", 1},   {"m33f", 36},    {"m33d", 72},
      {"m44f", 64},       {"m44d", 128},   {"rational", 8},
      {"tiledesc", 9},    {"timecode", 8}, {"v2i", 8},
      {"v2f", 8},         {"v2d", 16},     {"v3i", 12},
      {"v3f", 12},        {"v3d", 24},     {"deepImageState", 1}};
  if (const auto it = kFixed.find(type); it != kFixed.end()) return it->second;
  if (type != "chlist") return declared;
  // Channels: name \0, then pixel type, pLinear and 3 reserved bytes, x and y sampling (16
  // bytes); an empty name ends the list.
  const std::string value = read(valueAt, static_cast<size_t>(declared));
  for (size_t at = 0; at < value.size();) {
    if (value[at] == '\0') return at + 1;
    const size_t end = value.find('\0', at);
    if (end == std::string::npos) break;
    at = end + 1 + 16;
  }
  return UINT64_MAX;
}

// A corrupt header can declare a PNG chunk or an OpenEXR attribute of gigabytes; libpng then skips
// it a kilobyte at a time and OpenEXR allocates it (seconds and GiB of memory for a file of 300
// bytes). Both end in an error anyway, since the bytes are not there: say so first. Checks every
// chunk of a PNG (up to IEND) and every attribute of an OpenEXR file's first header; other formats
// pass unchecked.
void checkFraming(const ByteReader& read, uint64_t size, const std::filesystem::path& name) {
  const std::string magic = read(0, 8);
  if (magic.size() == 8 && magic == std::string("\x89PNG\r\n\x1a\n", 8)) {
    for (uint64_t at = 8; size - at >= 8;) {
      const std::string head = read(at, 8);
      const uint64_t length = bigEndian32(head, 0);
      const std::string type = printable(head.substr(4, 4));
      if (length > 0x7fffffffu || length + 12 > size - at)
        fail(name, "truncated or corrupt PNG: chunk \"" + type + "\" at byte " +
                       std::to_string(at) + " declares " + std::to_string(length) +
                       " bytes, the file has " + std::to_string(size - at) + " left");
      at += 12 + length;
      if (type == "IEND") break;
    }
  } else if (magic.size() == 8 && magic.compare(0, 4, "\x76\x2f\x31\x01") == 0) {
    // Attributes: name \0 type \0 size (int32, little-endian) value; an empty name ends the header.
    for (uint64_t at = 8; at < size;) {
      const std::string window = read(at, 2 * 256 + 8);
      if (window.empty() || window[0] == '\0') break;
      const size_t nameEnd = window.find('\0'), typeEnd = window.find('\0', nameEnd + 1);
      if (nameEnd == std::string::npos || typeEnd == std::string::npos ||
          typeEnd + 5 > window.size())
        fail(name, "truncated or corrupt OpenEXR header at byte " + std::to_string(at));
      const uint32_t raw = uint32_t(uint8_t(window[typeEnd + 1])) |
                           (uint32_t(uint8_t(window[typeEnd + 2])) << 8) |
                           (uint32_t(uint8_t(window[typeEnd + 3])) << 16) |
                           (uint32_t(uint8_t(window[typeEnd + 4])) << 24);
      const uint64_t valueAt = at + typeEnd + 5;
      const std::string attribute = printable(window.substr(0, nameEnd));
      if (raw > 0x7fffffffu || raw > size - valueAt)
        fail(name, "truncated or corrupt OpenEXR header: attribute \"" + attribute +
                       "\" declares " + std::to_string(raw) + " bytes, the file has " +
                       std::to_string(size - valueAt) + " left");
      // OpenEXR reads a value of a known type by its type, not by the declared size: where the two
      // differ it goes on reading the next attribute from elsewhere than this walk (and may find a
      // size of gigabytes there), so they must agree.
      const std::string type = window.substr(nameEnd + 1, typeEnd - nameEnd - 1);
      const uint64_t expected = exrValueSize(type, read, valueAt, raw);
      if (expected != raw)
        fail(name, "truncated or corrupt OpenEXR header: attribute \"" + attribute + "\" of type " +
                       printable(type) + " declares " + std::to_string(raw) +
                       " bytes, its value holds " +
                       (expected == UINT64_MAX ? std::string("no whole value")
                                               : std::to_string(expected)));
      at = valueAt + raw;
    }
  }
}

// An in-memory source for OpenImageIO that checks every offset. OpenImageIO 2.4's IOMemReader
// trusts them: OpenEXR seeking to a negative offset (a corrupt header) made it copy from before
// the buffer (heap-buffer-overflow found by fuzz_height_image), where a file would just fail.
class CheckedMemReader final : public OIIO::Filesystem::IOProxy {
 public:
  CheckedMemReader(const void* data, size_t size)
      : IOProxy("", Read), data_(static_cast<const unsigned char*>(data)), size_(size) {}
  const char* proxytype() const override { return "meso_memreader"; }
  bool seek(int64_t offset) override {
    if (offset < 0) return false;  // past the end is allowed, as for files: reads give 0 bytes
    m_pos = offset;
    return true;
  }
  size_t read(void* buf, size_t count) override {
    const size_t n = pread(buf, count, m_pos);
    m_pos += static_cast<int64_t>(n);
    return n;
  }
  size_t pread(void* buf, size_t count, int64_t offset) override {
    if (offset < 0 || static_cast<uint64_t>(offset) >= size_) return 0;
    const size_t n = static_cast<size_t>(std::min<uint64_t>(count, size_ - offset));
    std::memcpy(buf, data_ + offset, n);
    return n;
  }
  size_t size() const override { return size_; }

 private:
  const unsigned char* data_;
  size_t size_;
};

// Encodes into memory: OpenImageIO's file writers do not report every failed write (libpng's
// fwrite on a full disk went unnoticed: exit 0 with half a PNG), so meso writes the bytes itself.
std::string encodeWithOiio(const std::filesystem::path& name, const OIIO::ImageSpec& spec,
                           OIIO::TypeDesc format, const void* data) {
  auto out = OIIO::ImageOutput::create(name.extension().string().substr(1));
  if (!out) fail(name, "cannot create image writer: " + oiioMessage(""));
  if (!out->supports("ioproxy"))
    fail(name, std::string("the ") + out->format_name() + " writer cannot write to memory");
  std::vector<unsigned char> buffer;
  OIIO::Filesystem::IOVecOutput proxy(buffer);
  if (!out->set_ioproxy(&proxy))
    fail(name, "cannot write to memory: " + oiioMessage(out->geterror()));
  if (!out->open(name.string(), spec))
    fail(name, "cannot open for writing: " + oiioMessage(out->geterror()));
  if (!out->write_image(format, data)) fail(name, "write failed: " + oiioMessage(out->geterror()));
  if (!out->close()) fail(name, "close failed: " + oiioMessage(out->geterror()));
  out.reset();
  return std::string(buffer.begin(), buffer.end());
}

// IEC 61966-2-1 sRGB encoding of a linear value in [0, 1].
float srgbEncode(float v) {
  v = std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

// The pixels of an opened image, all channels as float; at most maxValues of them (0: no limit
// beyond OpenImageIO's and memoryLimitBytes).
Image readOpened(OIIO::ImageInput& in, const std::filesystem::path& file, uint64_t fileBytes,
                 uint64_t memoryLimitBytes, size_t maxValues = 0) {
  const OIIO::ImageSpec& spec = in.spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    fail(file, "image has zero size (" + std::to_string(spec.width) + "x" +
                   std::to_string(spec.height) + ", " + std::to_string(spec.nchannels) +
                   " channels)");
  // A corrupt header can declare any size: refuse (before allocating) what OpenImageIO's own limit
  // refuses, in double so that width x height x channels cannot overflow.
  const double mib = static_cast<double>(spec.width) * spec.height * spec.nchannels *
                     sizeof(float) / (1024.0 * 1024.0);
  const int limitMib = OIIO::get_int_attribute("limits:imagesize_MB", 32768);
  if (mib > limitMib)
    fail(file, "image too large (" + std::to_string(spec.width) + "x" +
                   std::to_string(spec.height) + ", " + std::to_string(spec.nchannels) +
                   " channels: " + std::to_string(static_cast<long long>(mib)) +
                   " MiB as float, more than OpenImageIO's limits:imagesize_MB = " +
                   std::to_string(limitMib) + ")");
  // Deflate compresses at most 1032:1: a PNG smaller than that share of its pixels is truncated or
  // lies about its size (decoding would allocate for pixels that are not there).
  const double rawBytes =
      static_cast<double>(spec.width) * spec.height * spec.nchannels * spec.format.size();
  if (std::string(in.format_name()) == "png" &&
      rawBytes > 1032.0 * static_cast<double>(fileBytes) + 65536.0)
    fail(file, "truncated or corrupt PNG: " + std::to_string(fileBytes) +
                   " bytes cannot hold the " + std::to_string(spec.width) + "x" +
                   std::to_string(spec.height) + " pixels its header declares");
  // Float pixels plus the native scanlines they are converted from: refused from the declared size,
  // before decoding (a 190-byte PNG declaring 60000 x 60000 once tried 13 GiB).
  requireMemoryWithin(memoryLimitBytes,
                      static_cast<double>(spec.width) * spec.height * spec.nchannels *
                          (sizeof(float) + spec.format.size()),
                      file.string(), "image",
                      "decoding " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                          ", " + std::to_string(spec.nchannels) +
                          " channels, as the header declares");
  const double values = static_cast<double>(spec.width) * spec.height * spec.nchannels;
  if (maxValues > 0 && values > static_cast<double>(maxValues))
    fail(file, "image too large (" + std::to_string(spec.width) + "x" +
                   std::to_string(spec.height) + ", " + std::to_string(spec.nchannels) +
                   " channels: more than " + std::to_string(maxValues) + " values)");
  Image image(spec.width, spec.height, spec.channelnames);
  bool ok;
  if (spec.tile_width > 0 || spec.depth > 1 || spec.deep || !spec.channelformats.empty()) {
    ok = in.read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data());
  } else {
    // Scanline images: the format's own scanline reader, then conversion here. read_image would go
    // through a conversion buffer of about 64 MiB whatever the image size: harmless while
    // untouched, but ASan allocates and poisons all of it for every image (the height-image fuzzer
    // spent most of its time there). The result is the same, bit for bit.
    std::vector<unsigned char> native(spec.image_bytes(true));
    ok = in.read_native_scanlines(0, 0, spec.y, spec.y + spec.height, spec.z, 0, spec.nchannels,
                                  native.data());
    constexpr size_t kBatch = size_t(1) << 24;  // convert_pixel_values counts in int
    for (size_t i = 0; ok && i < image.pixels.size(); i += kBatch)
      ok = OIIO::convert_pixel_values(spec.format, native.data() + i * spec.format.size(),
                                      OIIO::TypeDesc::FLOAT, image.pixels.data() + i,
                                      static_cast<int>(std::min(kBatch, image.pixels.size() - i)));
  }
  if (!ok) fail(file, "cannot read pixels (truncated or corrupt?): " + oiioMessage(in.geterror()));
  in.close();
  return image;
}

}  // namespace

Image readImage(const std::filesystem::path& file, uint64_t memoryLimitBytes) {
  if (!std::filesystem::exists(file)) fail(file, "no such file");
  checkInputFile(file, "image", kMaxImageBytes);
  {
    std::error_code ec;
    const uint64_t size = std::filesystem::file_size(file, ec);
    std::ifstream in(file, std::ios::binary);
    if (!ec && in) {
      checkFraming(
          [&](uint64_t offset, size_t count) {
            std::string b(count, '\0');
            in.clear();
            in.seekg(static_cast<std::streamoff>(offset));
            in.read(b.data(), static_cast<std::streamsize>(count));
            b.resize(static_cast<size_t>(std::max<std::streamsize>(in.gcount(), 0)));
            return b;
          },
          size, file);
    }
  }
  // Colour channels as stored, not multiplied by alpha: a height or data image with a
  // half-transparent alpha keeps its values (formats that store associated alpha, like OpenEXR,
  // are read as they are).
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(file.string(), &config);
  if (!in) fail(file, "cannot read image: " + oiioMessage(""));
  std::error_code ec;
  const uint64_t bytes = std::filesystem::file_size(file, ec);
  return readOpened(*in, file, ec ? UINT64_MAX / 2048 : bytes, memoryLimitBytes);
}

Image readImageFromMemory(const void* data, size_t size, const std::filesystem::path& name,
                          size_t maxValues, uint64_t memoryLimitBytes) {
  const char* bytes = static_cast<const char*>(data);
  checkFraming(
      [&](uint64_t offset, size_t count) {
        return offset >= size
                   ? std::string()
                   : std::string(bytes + offset, std::min<uint64_t>(count, size - offset));
      },
      size, name);
  // Declared before the reader, so that it outlives the reader's close() in its destructor.
  CheckedMemReader proxy(data, size);
  // create() with the bare extension ("png") picks that format's reader and nothing else. Given a
  // file name it would look for the file, and ImageInput::open would try every other format when
  // the bytes are not a valid image of this one.
  const std::string ext = name.extension().string();
  if (ext.size() < 2) fail(name, "no file extension to pick an image format by");
  auto in = OIIO::ImageInput::create(ext.substr(1));
  if (!in) fail(name, "cannot read image: " + oiioMessage(""));
  if (!in->supports("ioproxy"))
    fail(name, std::string("the ") + in->format_name() + " reader cannot read from memory");
  // The proxy goes in through the open configuration: readers take it from "oiio:ioproxy" there
  // (and drop one set by set_ioproxy() when the configuration has none).
  OIIO::ImageSpec config, spec;
  OIIO::Filesystem::IOProxy* proxyPointer = &proxy;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxyPointer);
  if (!in->open(name.string(), spec, config))
    fail(name, "cannot read image: " + oiioMessage(in->geterror()));
  return readOpened(*in, name, size, memoryLimitBytes, maxValues);
}

std::string encodeExr(const Image& image) {
  OIIO::ImageSpec spec(image.width, image.height, image.numChannels(), OIIO::TypeDesc::FLOAT);
  spec.channelnames = image.channels;
  spec.alpha_channel = image.channelIndex("A");
  // zlib's fastest level: 0.8-0.9x the default level's time for 1.004x the bytes (bench_image).
  spec.attribute("compression", "zip:1");
  spec.attribute("Software", "meso");
  // OpenEXR otherwise stamps the current time (capDate): the same render must give the same bytes.
  spec.attribute("DateTime", "");
  return encodeWithOiio("image.exr", spec, OIIO::TypeDesc::FLOAT, image.pixels.data());
}

std::string encodePngPreview(const Image& image) {
  const int rgb[3] = {image.channelIndex("R"), image.channelIndex("G"), image.channelIndex("B")};
  if (rgb[0] < 0 || rgb[1] < 0 || rgb[2] < 0) fail("preview.png", "image has no R, G, B channels");
  std::vector<uint8_t> bytes(static_cast<size_t>(image.width) * image.height * 3);
  tbb::parallel_for(0, image.height, [&](int y) {
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c)
        bytes[(static_cast<size_t>(y) * image.width + x) * 3 + c] =
            static_cast<uint8_t>(std::lround(255.0f * srgbEncode(image.at(x, y, rgb[c]))));
  });
  OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:ColorSpace", "sRGB");
  // A preview: zlib's fastest level, a quarter of the default level's time for 1.13x the bytes
  // (build/tools/bench_image).
  spec.attribute("png:compressionLevel", 1);
  return encodeWithOiio("preview.png", spec, OIIO::TypeDesc::UINT8, bytes.data());
}

void setImageThreads(int threads) {
  const int n = std::max(threads, 0);
  OIIO::attribute("threads", n);
  OIIO::attribute("exr_threads", n);
}

void writeExr(const std::filesystem::path& file, const Image& image) {
  checkOutputFile(file, "");
  writeFileAtomically(file, encodeExr(image));
}

void writePngPreview(const std::filesystem::path& file, const Image& image) {
  checkOutputFile(file, "");
  writeFileAtomically(file, encodePngPreview(image));
}

}  // namespace meso
