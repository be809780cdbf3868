// The meshes' colour textures (Mesh::colorTexture) for the camera pass: sampled sRGB images with
// mip chains (made on the device by blits), read with trilinear filtering and repeat. A white
// image stands in where a textured draw's mesh has none (a cut-out with an alpha map only).
#pragma once
#include <cstdint>
#include <vector>

#include "core/scene.h"
#include "gpu/context.h"
#include "gpu/resources.h"

namespace penumbra::raster {

class ColorTextures {
 public:
  ColorTextures(const gpu::Context& context, const Scene& scene);
  // Scene texture `texture`'s image, left in eShaderReadOnlyOptimal (white for -1).
  vk::ImageView view(std::int32_t texture) const;
  vk::Sampler sampler() const { return *sampler_; }
  vk::DeviceSize bytes() const;

 private:
  std::vector<gpu::Image> images_;      // [0]: white
  std::vector<std::uint32_t> imageOf_;  // per scene texture: its image, 0 for those no mesh colours with
  vk::raii::Sampler sampler_;
};

// The device memory ColorTextures takes for `scene` at its peak: each colour texture with its mip
// chain, and its staging copy while it uploads.
std::uint64_t colorTextureBytes(const Scene& scene);

}  // namespace penumbra::raster
