// The shading pass every method shares: G-buffer + visibility buffer (+ the indirect buffer of
// methods ao and indirect) -> sRGB RGBA8 image.
#pragma once
#include "gpu/pipeline.h"
#include "hybrid/method.h"
#include "raster/gbuffer_pass.h"

namespace penumbra {

class ShadePass {
 public:
  explicit ShadePass(const gpu::Context& context);
  void record(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer, const gpu::Buffer& frame,
              const gpu::Buffer& visibility, const gpu::Buffer& indirect, const gpu::Buffer& color, Term term) const;

 private:
  gpu::ComputePipeline pipeline_;
};

}  // namespace penumbra
