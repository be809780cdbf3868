// Reading PNGs back in tests (stb_image, a static copy per test binary so it cannot clash with
// libstb or another test file), and the "not blank" measure the image tests share.
#pragma once
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <map>
#include <utility>
#include <vector>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

namespace penumbra::test {

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;
};

// Empty (0 x 0) when the file is missing or not an image.
inline Image readPng(const std::filesystem::path& path) {
  Image image;
  int channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &image.width, &image.height, &channels, 4);
  if (!data) return {};
  image.rgba.assign(data, data + std::size_t(image.width) * image.height * 4);
  stbi_image_free(data);
  return image;
}

// Distinct colours and the share of the most common one: a blank image is one colour.
inline std::pair<std::size_t, double> colourSpread(const Image& image) {
  std::map<std::uint32_t, std::size_t> counts;
  for (std::size_t i = 0; i + 3 < image.rgba.size(); i += 4) {
    ++counts[std::uint32_t(image.rgba[i]) << 24 | std::uint32_t(image.rgba[i + 1]) << 16 |
             std::uint32_t(image.rgba[i + 2]) << 8 | image.rgba[i + 3]];
  }
  std::size_t top = 0;
  for (const auto& [colour, n] : counts) top = std::max(top, n);
  const std::size_t pixels = image.rgba.size() / 4;
  return {counts.size(), pixels == 0 ? 1.0 : double(top) / double(pixels)};
}

}  // namespace penumbra::test
