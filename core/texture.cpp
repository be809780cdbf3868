#include "core/texture.h"

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>

#include "core/scene_loader.h"

// stb_image is header-only; its functions are made static here so they cannot clash with the copy
// in libstb that other libraries link against. PNG and JPEG: what glTF allows without extensions.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_NO_STDIO
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

namespace penumbra {

Texture decodeTexture(std::span<const std::uint8_t> encoded, const std::string& name, int* channels) {
  const auto refuse = [&](const std::string& why) -> Texture {
    throw InputError("image '" + name + "' " + why + "; re-export the model with PNG or JPEG images");
  };
  if (encoded.empty()) return refuse("is empty");
  if (encoded.size() > std::size_t(INT32_MAX)) return refuse("is larger than 2 GiB");
  int width = 0, height = 0, own = 0;
  if (!stbi_info_from_memory(encoded.data(), int(encoded.size()), &width, &height, &own)) {
    return refuse(std::string("cannot be decoded (") + stbi_failure_reason() + ")");
  }
  if (width <= 0 || height <= 0 || std::uint32_t(width) > kMaxTextureSide || std::uint32_t(height) > kMaxTextureSide) {
    return refuse("is " + std::to_string(width) + "x" + std::to_string(height) + ", over the " +
                  std::to_string(kMaxTextureSide) + " texels a side accepted");
  }
  const std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
      stbi_load_from_memory(encoded.data(), int(encoded.size()), &width, &height, &own, 4), &stbi_image_free);
  if (!pixels) return refuse(std::string("cannot be decoded (") + stbi_failure_reason() + ")");
  if (channels != nullptr) *channels = own;
  Texture t;
  t.name = name;
  t.width = std::uint32_t(width);
  t.height = std::uint32_t(height);
  t.rgba.assign(pixels.get(), pixels.get() + std::size_t(width) * std::size_t(height) * 4);
  return t;
}

Texture readTexture(const std::string& folder, const std::string& name, const std::string& model) {
  const std::string why = confinedPathProblem(folder, name);
  if (!why.empty()) {
    throw InputError("'" + model + "': image '" + name + "' is outside the model's folder (" + why +
                     "); copy it beside the model");
  }
  std::ifstream in(std::filesystem::path(folder) / name, std::ios::binary);
  const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (!in.is_open() || in.bad())
    throw InputError("'" + model + "': image '" + name + "' could not be read; put it beside the model");
  int channels = 0;
  Texture t = decodeTexture(bytes, model + ": " + name, &channels);
  if (channels == 1 || channels == 3) {
    for (std::size_t i = 0; i + 3 < t.rgba.size(); i += 4) {
      t.rgba[i + 3] = std::uint8_t((299u * t.rgba[i] + 587u * t.rgba[i + 1] + 114u * t.rgba[i + 2] + 500u) / 1000u);
    }
  }
  return t;
}

glm::vec3 meanColor(const Texture& texture) {
  std::array<float, 256> linear{};
  for (std::size_t i = 0; i < linear.size(); ++i) {
    const float c = float(i) / 255.0f;
    linear[i] = c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
  }
  glm::dvec3 sum(0.0);
  for (std::size_t i = 0; i + 3 < texture.rgba.size(); i += 4) {
    sum += glm::dvec3(linear[texture.rgba[i]], linear[texture.rgba[i + 1]], linear[texture.rgba[i + 2]]);
  }
  const std::size_t texels = texture.rgba.size() / 4;
  return texels == 0 ? glm::vec3(1.0f) : glm::vec3(sum / double(texels));
}

}  // namespace penumbra
