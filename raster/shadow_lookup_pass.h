// Shadow-map lookup (methods sm and pcf): one visibility value per pixel from the light's centre,
// unfiltered or percentage-closer filtered (3x3, 5x5, Poisson disc).
#pragma once
#include "gpu/pipeline.h"
#include "raster/gbuffer_pass.h"
#include "raster/shadow_map_pass.h"

namespace penumbra::raster {

class ShadowLookupPass {
 public:
  explicit ShadowLookupPass(const gpu::Context& context);
  // frame holds FrameData (shadowFilter selects the kernel); visibility gets width*height floats.
  void record(const vk::raii::CommandBuffer& cmd, const GBufferPass& gbuffer, const ShadowMapPass& shadowMap,
              const gpu::Buffer& frame, const gpu::Buffer& visibility) const;

 private:
  gpu::ComputePipeline pipeline_;
};

}  // namespace penumbra::raster
