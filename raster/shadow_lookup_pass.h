// Shadow-map lookup: one visibility value per pixel from one shadow map, unfiltered or
// percentage-closer filtered (3x3, 5x5, Poisson disc, PCSS). Methods sm, pcf and pcss overwrite
// the visibility buffer; msm accumulates a weighted sum over several maps.
#pragma once
#include "gpu/pipeline.h"
#include "raster/gbuffer_pass.h"
#include "raster/shadow_map_pass.h"

namespace penumbra::raster {

class ShadowLookupPass {
 public:
  explicit ShadowLookupPass(const gpu::Context& context);
  // frame holds FrameData (shadowFilter selects the kernel); visibility gets width*height floats.
  // The dispatch covers lightRect, FrameData's light rectangle as pixels [xy, zw); beyond it the
  // light reaches nothing: 0. accumulateWeight 0 overwrites; > 0 adds accumulateWeight * visibility
  // to what is there.
  void record(const vk::raii::CommandBuffer& cmd, const GBufferPass& gbuffer, const ShadowMapPass& shadowMap,
              const gpu::Buffer& frame, const gpu::Buffer& visibility, glm::uvec4 lightRect,
              float accumulateWeight = 0.0f) const;

 private:
  gpu::SpecializedComputePipeline pipeline_;  // on texelReads()
};

}  // namespace penumbra::raster
