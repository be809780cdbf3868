// Tracers answer shadow rays for a dense list of shading points that lives in GPU buffers (host
// visible, so CPU tracers read the same list). GPU tracers record an indirect dispatch driven by
// the count the compaction wrote; CPU tracers do their work after the submission completed.
#pragma once
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "core/scene.h"
#include "gpu/pipeline.h"
#include "gpu/resources.h"
#include "raytrace/bvh_refit.h"
#include "shared/frame.h"
#include "shared/shading_point.h"
#include "shared/trace.h"

namespace penumbra {

struct TraceJob {
  // shared::ShadingPoint[capacity]; the first `count` are valid. GPU kernels read it through its
  // device address, frame's FrameData::tracePoints (shaders/point_list.glsl); the host reads it here.
  const gpu::Buffer& points;
  const gpu::Buffer& count;       // shared::TraceCount (count + indirect dispatch size)
  const gpu::Buffer& frame;       // shared::FrameData (the light; traceInPlace)
  const gpu::Buffer& visibility;  // float per pixel; the tracer writes visibility[point.pixel]
  // The G-buffer's position and normal (storage images, GENERAL): GPU tracers bind them and trace
  // every covered pixel from them instead of the list when FrameData::traceInPlace is set.
  vk::ImageView position, normal;

  // Adds the job to a shadow-ray kernel's descriptors: count, frame and visibility at
  // firstBuffer.. firstBuffer + 2 (where each kernel declares them), the G-buffer at
  // TRACE_BINDING_POSITION / TRACE_BINDING_NORMAL (trace_points.glsl). Throws
  // std::invalid_argument when a job that reads the list has a frame that does not point to it.
  gpu::Descriptors& addTo(gpu::Descriptors& descriptors, std::uint32_t firstBuffer) const {
    const auto* data = static_cast<const shared::FrameData*>(frame.data());
    if (!data->traceInPlace && (data->tracePoints != gpu::addressHalves(points) ||
                                std::uint64_t(data->traceCapacity) * sizeof(shared::ShadingPoint) > points.size())) {
      throw std::invalid_argument("TraceJob: the frame's FrameData::tracePoints is not the job's points buffer");
    }
    return descriptors.buffer(firstBuffer, count)
        .buffer(firstBuffer + 1, frame)
        .buffer(firstBuffer + 2, visibility)
        .storageImage(TRACE_BINDING_POSITION, position)
        .storageImage(TRACE_BINDING_NORMAL, normal);
  }
};

struct TraceReport {
  std::uint64_t rays = 0;                      // shadow rays actually traced
  std::optional<std::uint64_t> nodeVisits;     // traversal steps, where the tracer counts them
  std::optional<std::uint64_t> triangleTests;
  double hostMs = 0.0;                         // CPU time spent in finish()
};

// What a GPU tracer's record() starts with: the compaction's compute writes (points, count, the
// indirect arguments) ordered before the trace, earlier compute work that may still use the counters
// and the visibility buffer ordered before their reuse, then the counters zeroed on the GPU.
inline void recordTraceStart(const vk::raii::CommandBuffer& cmd, const gpu::Buffer& counters) {
  using Stage = vk::PipelineStageFlagBits2;
  using Access = vk::AccessFlagBits2;
  gpu::memoryBarrier(
      cmd, Stage::eComputeShader, Access::eShaderStorageWrite,
      Stage::eDrawIndirect | Stage::eComputeShader | Stage::eTransfer,
      Access::eIndirectCommandRead | Access::eShaderStorageRead | Access::eShaderStorageWrite | Access::eTransferWrite);
  cmd.fillBuffer(counters.handle(), 0, VK_WHOLE_SIZE, 0u);
  gpu::memoryBarrier(cmd, Stage::eTransfer, Access::eTransferWrite, Stage::eComputeShader,
                     Access::eShaderStorageRead | Access::eShaderStorageWrite);
}

class ShadowTracer {
 public:
  virtual ~ShadowTracer() = default;
  virtual std::string name() const = 0;  // "bvh", "embree", ...
  // A GPU tracer: its trace is done when the submission that recorded it is, and it can take its
  // points straight from the G-buffer (TraceJob, trace_points.glsl).
  virtual bool onDevice() const { return false; }
  // GPU tracers record their trace here (before the submission); CPU tracers record nothing.
  virtual void record(const vk::raii::CommandBuffer& cmd, const TraceJob& job) = 0;
  // After the submission completed: CPU tracers trace here; every tracer reports its counters.
  virtual TraceReport finish(const TraceJob& job) = 0;
  // The scene's dynamic meshes moved: refit (or rebuild) what the tracer traces and report it, or
  // nullopt where it cannot follow them (its owner then builds it again on next use).
  virtual std::optional<BvhRefitReport> sceneMoved(const Scene& scene) = 0;
};

}  // namespace penumbra
