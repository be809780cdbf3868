#include "core/image_io.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <tinyexr.h>  // the implementation lives in the shared libtinyexr

// stb_image_write is header-only; its functions are made static here so they cannot clash with the
// copy in libstb that other libraries (tinygltf) link against.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

namespace penumbra {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error("cannot write image '" + path + "': " + what);
}

std::size_t checkedPixels(const std::string& path, int width, int height, std::size_t have,
                          std::size_t perPixel) {
  if (width <= 0 || height <= 0) fail(path, "image size must be positive");
  const std::size_t pixels = std::size_t(width) * std::size_t(height);
  if (have != pixels * perPixel) {
    fail(path, "expected " + std::to_string(pixels * perPixel) + " values, got " + std::to_string(have));
  }
  return pixels;
}

// CRC-32 (ISO-HDLC polynomial, reflected) as PNG chunks require.
std::uint32_t crc32(std::uint32_t crc, const std::uint8_t* data, std::size_t size) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  crc = ~crc;
  for (std::size_t i = 0; i < size; ++i) crc = table[(crc ^ data[i]) & 0xFFu] ^ (crc >> 8);
  return ~crc;
}

void putBigEndian32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  out.push_back(std::uint8_t(v >> 24));
  out.push_back(std::uint8_t(v >> 16));
  out.push_back(std::uint8_t(v >> 8));
  out.push_back(std::uint8_t(v));
}

void putChunk(std::vector<std::uint8_t>& out, const char type[4], const std::uint8_t* data, std::size_t size) {
  putBigEndian32(out, std::uint32_t(size));
  const std::size_t typeAt = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data, data + size);
  // The CRC covers the chunk type and data, not the length.
  putBigEndian32(out, crc32(0, out.data() + typeAt, size + 4));
}

void writeFile(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) fail(path, "cannot open the file for writing (does the folder exist?)");
  file.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  file.close();
  if (!file) fail(path, "write failed");
}

struct StbFree {
  void operator()(unsigned char* p) const { STBIW_FREE(p); }
};
struct ErrFree {
  void operator()(const char* p) const { FreeEXRErrorMessage(p); }
};
using ErrPtr = std::unique_ptr<const char, ErrFree>;

std::string exrMessage(int code, const char* err) {
  return err ? std::string(err) : "tinyexr error " + std::to_string(code);
}

}  // namespace

void writePngRgba8(const std::string& path, int width, int height, std::span<const std::uint8_t> rgba) {
  checkedPixels(path, width, height, rgba.size(), 4);
  if (!stbi_write_png(path.c_str(), width, height, 4, rgba.data(), width * 4)) {
    fail(path, "cannot open or write the file (does the folder exist?)");
  }
}

void writePngGray16(const std::string& path, int width, int height, std::span<const float> values) {
  checkedPixels(path, width, height, values.size(), 1);
  const std::size_t rowBytes = 1 + 2 * std::size_t(width);
  const std::size_t rawSize = rowBytes * std::size_t(height);
  if (rawSize > std::size_t(std::numeric_limits<int>::max())) fail(path, "image too large for PNG output");

  // Raw scanlines: filter type 0 (none), then big-endian 16-bit samples as PNG mandates.
  std::vector<std::uint8_t> raw(rawSize);
  for (int y = 0; y < height; ++y) {
    std::uint8_t* row = &raw[std::size_t(y) * rowBytes];
    row[0] = 0;
    for (int x = 0; x < width; ++x) {
      const float v = values[std::size_t(y) * std::size_t(width) + std::size_t(x)];
      const float c = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
      const auto s = static_cast<std::uint16_t>(std::lround(c * 65535.0f));
      row[1 + 2 * x] = std::uint8_t(s >> 8);
      row[2 + 2 * x] = std::uint8_t(s & 0xFFu);
    }
  }
  int zlibSize = 0;
  std::unique_ptr<unsigned char, StbFree> zlib(stbi_zlib_compress(raw.data(), int(rawSize), &zlibSize, 8));
  if (!zlib || zlibSize <= 0) fail(path, "compression failed");

  std::vector<std::uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  std::vector<std::uint8_t> ihdr;
  putBigEndian32(ihdr, std::uint32_t(width));
  putBigEndian32(ihdr, std::uint32_t(height));
  ihdr.insert(ihdr.end(), {16, 0, 0, 0, 0});  // bit depth 16, grey, deflate, adaptive filter, no interlace
  putChunk(png, "IHDR", ihdr.data(), ihdr.size());
  putChunk(png, "IDAT", zlib.get(), std::size_t(zlibSize));
  putChunk(png, "IEND", nullptr, 0);
  writeFile(path, png);
}

void writeExrGray(const std::string& path, int width, int height, std::span<const float> values) {
  checkedPixels(path, width, height, values.size(), 1);
  // tinyexr takes non-const pointers; a copy keeps the caller's buffer untouched.
  std::vector<float> data(values.begin(), values.end());
  unsigned char* channelData[1] = {reinterpret_cast<unsigned char*>(data.data())};

  EXRImage image;
  InitEXRImage(&image);
  image.num_channels = 1;
  image.images = channelData;
  image.width = width;
  image.height = height;

  EXRHeader header;
  InitEXRHeader(&header);
  EXRChannelInfo channel{};
  std::strncpy(channel.name, "Y", sizeof(channel.name) - 1);
  int pixelType = TINYEXR_PIXELTYPE_FLOAT;
  int requestedType = TINYEXR_PIXELTYPE_FLOAT;
  header.num_channels = 1;
  header.channels = &channel;
  header.pixel_types = &pixelType;
  header.requested_pixel_types = &requestedType;  // FLOAT keeps every bit (no half conversion)
  header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;  // lossless

  const char* err = nullptr;
  const int rc = SaveEXRImageToFile(&image, &header, path.c_str(), &err);
  ErrPtr errGuard(err);
  // The header and image point at locals, so they are deliberately not passed to FreeEXR*.
  if (rc != TINYEXR_SUCCESS) fail(path, exrMessage(rc, err));
}

std::vector<float> readExrGray(const std::string& path, int& width, int& height) {
  auto readFail = [&](const std::string& what) -> std::runtime_error {
    return std::runtime_error("cannot read EXR '" + path + "': " + what);
  };
  EXRVersion version;
  int rc = ParseEXRVersionFromFile(&version, path.c_str());
  if (rc != TINYEXR_SUCCESS) throw readFail("not an OpenEXR file or cannot be opened (code " + std::to_string(rc) + ")");
  if (version.multipart || version.non_image || version.tiled) throw readFail("only single-part scanline images are supported");

  EXRHeader header;
  InitEXRHeader(&header);
  const char* err = nullptr;
  rc = ParseEXRHeaderFromFile(&header, &version, path.c_str(), &err);
  ErrPtr headerErr(err);
  if (rc != TINYEXR_SUCCESS) throw readFail(exrMessage(rc, err));
  struct HeaderGuard {
    EXRHeader* h;
    ~HeaderGuard() { FreeEXRHeader(h); }
  } headerGuard{&header};

  int channel = -1;
  for (int c = 0; c < header.num_channels; ++c) {
    if (std::strcmp(header.channels[c].name, "Y") == 0) channel = c;
  }
  if (channel < 0 && header.num_channels == 1) channel = 0;  // a lone channel of any name is grey
  if (channel < 0) throw readFail("no 'Y' channel");
  if (header.pixel_types[channel] == TINYEXR_PIXELTYPE_UINT) throw readFail("integer channel, expected float");
  for (int c = 0; c < header.num_channels; ++c) {
    if (header.pixel_types[c] == TINYEXR_PIXELTYPE_HALF) header.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
  }

  EXRImage image;
  InitEXRImage(&image);
  err = nullptr;
  rc = LoadEXRImageFromFile(&image, &header, path.c_str(), &err);
  ErrPtr imageErr(err);
  if (rc != TINYEXR_SUCCESS) throw readFail(exrMessage(rc, err));
  struct ImageGuard {
    EXRImage* i;
    ~ImageGuard() { FreeEXRImage(i); }
  } imageGuard{&image};
  if (!image.images || image.width <= 0 || image.height <= 0) throw readFail("no scanline image data");

  width = image.width;
  height = image.height;
  const auto* src = reinterpret_cast<const float*>(image.images[channel]);
  return std::vector<float>(src, src + std::size_t(width) * std::size_t(height));
}

}  // namespace penumbra
