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
  // A frame of several lights (a shadow term), its lights in the order they run. beginLights starts
  // it (every submission before has finished). Each light joins the batch being filled where it
  // fits (else shade the batch first: recordBatch), its visibility over the pixels [rect.xy,
  // rect.zw) its range reaches either copied from `visibility` (recordLight) or written by the
  // batch's trace (addTracedLight: one trace for all of the batch's traced lights, recorded by the
  // frame between prepareBatch and recordBatch).
  void beginLights(std::uint32_t count, std::uint32_t width, std::uint32_t height);
  bool fits(const glm::uvec4& rect) const;
  void recordLight(const vk::raii::CommandBuffer& cmd, const gpu::Buffer& visibility, const shared::GpuLight& light,
                   const glm::uvec4& rect, std::uint32_t index);
  void addTracedLight(const shared::GpuLight& light, const glm::uvec4& rect, std::uint32_t index);
  bool batchTraces() const;  // the batch holds lights its trace writes
  // The batch's lists, uploaded, for its trace and its shading: the ShadeLight list and the
  // SHADE_TILE tile lists (tilesX per row) by device address, and the tiles its traced lights cover
  // ([xy, zw), whole tiles, possibly past the image's edge).
  struct Lists {
    gpu::Buffer lights, tiles;
  };
  struct BatchLists {
    const Lists& lists;
    std::uint32_t tilesX;
    glm::uvec4 traced;
  };
  BatchLists prepareBatch(std::uint32_t width, std::uint32_t height);
  const gpu::Buffer& batchVisibility() const { return *batchVisibility_; }
  // Shades the prepared batch, into the image where `last` (the frame's last light), else into the
  // direct light so far; empties the batch.
  void recordBatch(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer, const gpu::Buffer& frame,
                   const gpu::Buffer& color, bool last);
  // After the submission of a batch that traced: each traced light's index, rectangle, rays, and
  // where its visibility over the rectangle lies in batchVisibility() (row by row) until the batch
  // buffer is written again.
  struct TracedLight {
    std::uint32_t index;
    glm::uvec4 rect;
    std::uint64_t rays;
    std::uint32_t offset;
  };
  std::vector<TracedLight> tracedLights() const;
  // Light visibilities a batch holds at most, in images: more lights take more batches.
  static constexpr std::uint32_t kBatchImages = 16;
  std::uint32_t batches() const { return batches_; }  // the last frame of several lights'
  vk::DeviceSize batchBytes() const { return batchVisibility_ ? batchVisibility_->size() : 0; }

 private:
  void add(const shared::GpuLight& light, const glm::uvec4& rect, std::uint32_t index, bool traced);
  // The pixels the batch's lights (or its traced ones only) reach: their rectangles' union, empty
  // (zw < xy) where none.
  glm::uvec4 reach(std::uint32_t width, std::uint32_t height, bool tracedOnly) const;
  void dispatch(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer, const gpu::Buffer& frame,
                const gpu::Buffer& visibility, const gpu::Buffer& indirect, const gpu::Buffer& direct,
                const gpu::Buffer& color, const gpu::Buffer& lights, const gpu::Buffer& tiles,
                const shared::ShadePush& push, const glm::uvec4& rect) const;
  const gpu::Context& context_;
  gpu::ComputePipeline pipeline_;
  // The batch being filled, and each batch's lists of a frame (kept across frames: a list is
  // rewritten only once its frame is done).
  std::unique_ptr<gpu::Buffer> batchVisibility_;
  std::vector<shared::ShadeLight> batch_;
  std::uint64_t batchFloats_ = 0;  // of batchVisibility_ used by batch_
  std::vector<std::unique_ptr<Lists>> lists_;
  std::uint32_t batches_ = 0;            // this frame's batches shaded so far
  std::uint32_t tilesX_ = 0;             // of the prepared batch's lists
  std::unique_ptr<gpu::Buffer> direct_;  // frames of several batches: the direct light so far
  std::vector<std::uint32_t> tiles_;     // the batch's tile lists, as uploaded
  std::vector<vk::BufferCopy> rows_;     // a light's rectangle, row by row
  const Lists* shaded_ = nullptr;        // the last batch recordBatch shaded, and its lights
  std::size_t shadedLights_ = 0;
  std::uint32_t imageWidth_ = 0;
};

}  // namespace penumbra
