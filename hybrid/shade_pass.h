// The shading pass every method shares: G-buffer + visibility buffer (+ the indirect buffer of
// methods ao and indirect) -> sRGB RGBA8 image. With several lights it runs once per light, light
// `light` of `lights`: each adds its direct light into `direct` and the last writes the image.
#pragma once
#include "gpu/pipeline.h"
#include "hybrid/method.h"
#include "raster/gbuffer_pass.h"

namespace penumbra {

class ShadePass {
 public:
  explicit ShadePass(const gpu::Context& context);
  void record(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer, const gpu::Buffer& frame,
              const gpu::Buffer& visibility, const gpu::Buffer& indirect, const gpu::Buffer& direct,
              const gpu::Buffer& color, Term term, std::uint32_t light, std::uint32_t lights,
              const glm::uvec4& rect) const;  // pixels [rect.xy, rect.zw)

 private:
  gpu::ComputePipeline pipeline_;
};

}  // namespace penumbra
