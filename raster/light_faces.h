// Rendering into a light's depth faces, shared by the light passes (shadow map, thin mask):
// every face cleared to 1.0 and drawn by `drawFace`, then the image left in SHADER_READ_ONLY
// layout for compute lookups.
#pragma once
#include <cstdint>
#include <functional>

#include "gpu/resources.h"
#include "shared/frame.h"

namespace penumbra::raster {

// With `texels`, the depths are also copied there (one float per texel, face after face) and made
// visible to compute: storage-buffer reads are far cheaper than sampled-image fetches on lavapipe.
// Throws std::logic_error when `info` does not match the image's faces or resolution.
void recordLightFaces(const vk::raii::CommandBuffer& cmd, const gpu::Image& depth, const shared::ShadowMapInfo& info,
                      const std::function<void(std::uint32_t face)>& drawFace, const gpu::Buffer* texels = nullptr);

}  // namespace penumbra::raster
