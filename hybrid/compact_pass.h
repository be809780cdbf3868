// Compaction: the sparse per-pixel trace flags (or the coverage alone) -> a dense, tile-ordered
// list of ShadingPoints, its count and the trace kernel's indirect dispatch size.
// Three compute dispatches, reduce-then-scan (shaders/shared/compact.h describes them).
// Limits: the scan itself handles any pixel count below 2^32 - COMPACT_BLOCK_PIXELS (16384^2 is
// 32768 blocks; the constructor throws above). The points are written and read through their
// device address (shaders/point_list.glsl), not a binding, so one buffer bounds them: record()
// throws when 48 bytes per pixel exceed it (2 GiB on lavapipe: 44 M pixels).
#pragma once
#include <cstdint>

#include "gpu/pipeline.h"
#include "raster/gbuffer_pass.h"
#include "shared/frame.h"

namespace penumbra {

class CompactPass {
 public:
  CompactPass(const gpu::Context& context, std::uint32_t width, std::uint32_t height);

  // Size of each caller-owned per-pixel input: traceFlags (uint, nonzero = trace) and rayMax
  // (float, copied into ShadingPoint.rayMax; 0 = rays end at the light).
  static vk::DeviceSize inputBytes(std::uint32_t width, std::uint32_t height) {
    return vk::DeviceSize(width) * height * 4;
  }

  // mode: COMPACT_FLAGGED lists covered pixels whose flag is nonzero; COMPACT_ALL_COVERED lists
  // every covered pixel (traceFlags is bound but not read). A flag on an uncovered pixel
  // (G-buffer position w == 0) is ignored. Optionally | COMPACT_SHARED_SCAN (no subgroup scan).
  // Each point gets spp = frame.spp (frame holds FrameData, whose list describeList filled;
  // std::invalid_argument otherwise). The G-buffer must be in GENERAL
  // layout with its writes visible to compute (GBufferPass::record leaves it so), and the inputs'
  // writes made visible to compute by their producer.
  // Afterwards points() and count() are visible to compute, indirect-command reads and the host.
  void record(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer, const gpu::Buffer& traceFlags,
              const gpu::Buffer& rayMax, const gpu::Buffer& frame, std::uint32_t mode) const;

  // ShadingPoint[width * height]: the first count() entries are valid, in tile order (shared/compact.h).
  const gpu::Buffer& points() const { return points_; }
  // Points the kernels to this list: FrameData::tracePoints (its address) and traceCapacity.
  void describeList(shared::FrameData& frame) const;
  // TraceCount: count, then the VkDispatchIndirectCommand {ceil(count / TRACE_GROUP_SIZE), 1, 1}
  // at byte offset 4 (eIndirectBuffer usage).
  const gpu::Buffer& count() const { return count_; }
  vk::DeviceSize bytes() const { return points_.size() + count_.size() + mask_.size() + blocks_.size(); }
  std::uint32_t width() const { return width_; }
  std::uint32_t height() const { return height_; }

 private:
  std::uint32_t width_, height_;
  std::uint32_t blockCount_;
  std::uint32_t gridX_, gridY_;  // workgroups of the per-block dispatches
  std::uint64_t maxListBytes_;
  gpu::Buffer mask_;    // one selection bit per pixel, COMPACT_ITEMS per word
  gpu::Buffer blocks_;  // per block: selected pixels, then exclusive offsets
  gpu::Buffer points_;
  gpu::Buffer count_;
  gpu::ComputePipeline scan_, blockScan_, scatter_;
};

}  // namespace penumbra
