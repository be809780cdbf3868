// The shading pass every method shares: G-buffer + visibility buffer (+ the indirect buffer of
// methods ao and indirect) -> sRGB RGBA8 image. A frame of several lights keeps each light's
// visibility over the rectangle its range reaches and shades the lights a batch at a time: one pass
// per batch, each pixel looping over the lights its SHADE_TILE tile lists; the batches before the
// last write the direct light so far, which the next adds.
#pragma once
#include <memory>
#include <vector>

#include "gpu/pipeline.h"
#include "hybrid/method.h"
#include "raster/gbuffer_pass.h"
#include "shared/raster.h"

namespace penumbra {

class ShadePass {
 public:
  explicit ShadePass(const gpu::Context& context);
  // The frame's one light (FrameData's), visibility per pixel: the image.
  void record(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer, const gpu::Buffer& frame,
              const gpu::Buffer& visibility, const gpu::Buffer& indirect, const gpu::Buffer& color, Term term) const;
  // Light `order` of a frame's `count` (count > 1, a shadow term): its visibility over the pixels
  // [rect.xy, rect.zw) joins the batch, which is shaded where it is full and, with the last light,
  // into the image.
  void recordLight(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer, const gpu::Buffer& frame,
                   const gpu::Buffer& visibility, const gpu::Buffer& color, const shared::GpuLight& light,
                   const glm::uvec4& rect, std::uint32_t order, std::uint32_t count);
  // Light visibilities a batch holds at most, in images: more lights take more batches.
  static constexpr std::uint32_t kBatchImages = 16;
  std::uint32_t batches() const { return batches_; }  // the last frame of several lights'
  vk::DeviceSize batchBytes() const { return batchVisibility_ ? batchVisibility_->size() : 0; }

 private:
  void recordBatch(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer, const gpu::Buffer& frame,
                   const gpu::Buffer& color, bool last);
  void dispatch(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer, const gpu::Buffer& frame,
                const gpu::Buffer& visibility, const gpu::Buffer& indirect, const gpu::Buffer& direct,
                const gpu::Buffer& color, const gpu::Buffer& lights, const gpu::Buffer& tiles,
                const shared::ShadePush& push, const glm::uvec4& rect) const;
  const gpu::Context& context_;
  gpu::ComputePipeline pipeline_;
  // The batch being filled, and each batch's lists of a frame (kept across frames: a list is
  // rewritten only once its frame is done).
  struct Lists {
    gpu::Buffer lights, tiles;
  };
  std::unique_ptr<gpu::Buffer> batchVisibility_;
  std::vector<shared::ShadeLight> batch_;
  std::uint64_t batchFloats_ = 0;  // of batchVisibility_ used by batch_
  std::vector<std::unique_ptr<Lists>> lists_;
  std::uint32_t batches_ = 0;            // this frame's batches shaded so far
  std::unique_ptr<gpu::Buffer> direct_;  // frames of several batches: the direct light so far
  std::vector<std::uint32_t> tiles_;     // the batch's tile lists, as uploaded
  std::vector<vk::BufferCopy> rows_;     // a light's rectangle, row by row
};

}  // namespace penumbra
