// Decoding a model's images (PNG, JPEG) into Scene textures, with the checks an untrusted file needs.
#pragma once
#include <cstdint>
#include <span>
#include <string>

#include <glm/glm.hpp>

#include "core/scene.h"

namespace penumbra {

// The largest image side accepted, and the most bytes all decoded textures of a scene may take.
inline constexpr std::uint32_t kMaxTextureSide = 16384;
inline constexpr std::uint64_t kMaxTextureBytes = std::uint64_t(2) << 30;

// Decodes PNG or JPEG bytes to RGBA8. InputError naming `name` for an empty, corrupt or unsupported
// image or one with a side over kMaxTextureSide (checked from the header, before decoding).
// `channels`, when given, gets the image's own channel count (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA).
Texture decodeTexture(std::span<const std::uint8_t> encoded, const std::string& name, int* channels = nullptr);

// Reads image `name`, which the model file `model` names, from the model's folder `folder` and
// decodes it. Where the image has no alpha channel its luminance is its alpha (the default channel
// of OBJ's map_d and of opacity maps). InputError for an image outside the folder (see
// confinedPathProblem), missing, or one decodeTexture refuses.
Texture readTexture(const std::string& folder, const std::string& name, const std::string& model);

// The mean of a texture's colour, linear (its texels are sRGB): what a coarse consumer of a
// textured mesh's colour takes (the indirect tracers' per-triangle albedo).
glm::vec3 meanColor(const Texture& texture);

}  // namespace penumbra
