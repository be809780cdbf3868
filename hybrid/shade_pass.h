// The shading pass every method shares: G-buffer + visibility buffer (+ the indirect buffer of
// methods ao and indirect) -> sRGB RGBA8 image. A frame of several lights shades them in batches
// (ShadeBatch); the batches before the last write the direct light so far into `direct`.
#pragma once
#include "gpu/pipeline.h"
#include "hybrid/method.h"
#include "raster/gbuffer_pass.h"

namespace penumbra {

// A batch of a frame's lights one pass adds: shared::ShadeLight each in `lights`, listed per
// SHADE_TILE tile in `tiles` (tilesX per row), their visibilities in the pass's visibility buffer.
struct ShadeBatch {
  const gpu::Buffer& lights;
  const gpu::Buffer& tiles;
  std::uint32_t tilesX;
  bool last;  // writes the image (else the direct light so far)
  bool sum;   // adds the direct light of the batches before
};

class ShadePass {
 public:
  explicit ShadePass(const gpu::Context& context);
  // The frame's one light (FrameData's), visibility per pixel: the image.
  void record(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer, const gpu::Buffer& frame,
              const gpu::Buffer& visibility, const gpu::Buffer& indirect, const gpu::Buffer& color, Term term) const;
  // A batch of the frame's lights over pixels [rect.xy, rect.zw).
  void record(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer, const gpu::Buffer& frame,
              const gpu::Buffer& visibility, const gpu::Buffer& direct, const gpu::Buffer& color,
              const ShadeBatch& batch, const glm::uvec4& rect) const;

 private:
  void dispatch(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer, const gpu::Buffer& frame,
                const gpu::Buffer& visibility, const gpu::Buffer& indirect, const gpu::Buffer& direct,
                const gpu::Buffer& color, const gpu::Buffer& lights, const gpu::Buffer& tiles,
                const shared::ShadePush& push, const glm::uvec4& rect) const;
  gpu::ComputePipeline pipeline_;
};

}  // namespace penumbra
