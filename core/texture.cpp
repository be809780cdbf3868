#include "core/texture.h"

#include <memory>

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

}  // namespace penumbra
