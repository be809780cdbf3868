// The line-space tracer (Keul et al. 2017): the binary line space of the scene's N-tree
// (raytrace/line_space) in three storage buffers, shadow rays for a TraceJob by an indirect
// dispatch of linespace_trace.comp. No geometry is stored or tested: a ray is occluded when the
// shaft it runs through at the second-to-last level meets a non-empty cell, so shadows are
// conservative (slightly too dark), except that the finest node holding the ray's start casts no
// shadow on it (the paper's start-node skip).
#pragma once
#include <string>

#include "gpu/pipeline.h"
#include "raytrace/line_space.h"
#include "raytrace/shadow_tracer.h"

namespace penumbra {

class LineSpaceTracer final : public ShadowTracer {
 public:
  // Builds and uploads the line space. Throws InputError for bad (N, d), an empty scene, or pools
  // over the budget or over the device's maxStorageBufferRange (128 MiB on lavapipe), and
  // std::runtime_error when the device lacks subgroup arithmetic in compute shaders.
  LineSpaceTracer(const gpu::Context& context, const Scene& scene, const LineSpaceSettings& settings = {});

  std::string name() const override { return "ls"; }
  // Resets the counters and records the indirect trace, with the same barriers as BvhTracer.
  void record(const vk::raii::CommandBuffer& cmd, const TraceJob& job) override;
  TraceReport finish(const TraceJob& job) override;  // rays and node visits of the last record()

  const LineSpaceStats& stats() const { return stats_; }

 private:
  LineSpaceTracer(const gpu::Context& context, LineSpace lineSpace, float startOffsetCells);

  LineSpaceStats stats_;
  shared::LsPush push_{};
  gpu::Buffer tree_;
  gpu::Buffer nodes_;
  gpu::Buffer bits_;
  gpu::Buffer counters_;  // LS_COUNTER_WORDS uint
  gpu::ComputePipeline pipeline_;
};

}  // namespace penumbra
