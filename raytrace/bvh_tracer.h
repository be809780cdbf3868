// The GPU BVH tracer: the scene's BVH (BvhBuilder) in two storage buffers, shadow rays for a
// TraceJob by an indirect dispatch of bvh_trace.comp, and arbitrary rays through bvh_rays.comp.
#pragma once
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gpu/pipeline.h"
#include "raytrace/bvh_builder.h"
#include "raytrace/shadow_tracer.h"

namespace penumbra {

class BvhTracer final : public ShadowTracer {
 public:
  // Builds and uploads the BVH. Throws InputError when the scene is empty or its BVH would not fit
  // one storage buffer binding of this device (maxStorageBufferRange; 128 MiB on lavapipe), and
  // std::runtime_error when the device lacks subgroup arithmetic in compute shaders.
  BvhTracer(const gpu::Context& context, const Scene& scene, const BvhBuildSettings& settings = {});

  std::string name() const override { return "bvh"; }
  // Resets the counters and records the indirect trace; its barriers order it after the compute
  // pass that wrote job.points / job.count and before later compute passes and host reads.
  void record(const vk::raii::CommandBuffer& cmd, const TraceJob& job) override;
  TraceReport finish(const TraceJob& job) override;  // the counters of the last record() (each resets them)

  const BvhStats& stats() const { return stats_; }
  // The uploaded BVH, host visible (for the bandwidth model): BvhNode and BvhTriangle arrays.
  const gpu::Buffer& nodeBuffer() const { return nodes_; }
  const gpu::Buffer& triangleBuffer() const { return triangles_; }

  // Traces `rays` now (own submissions, waits). anyHit: each hit is the first one found, not
  // necessarily the nearest; closest-hit otherwise. A miss has t < 0 and triangle BVH_NO_HIT.
  std::vector<shared::RayHit> traceRays(std::span<const shared::RayQuery> rays, bool anyHit);
  // Rays, node visits and triangle tests of the last traceRays call.
  const TraceReport& lastRaysReport() const { return raysReport_; }

 private:
  BvhTracer(const gpu::Context& context, Bvh bvh);
  static TraceReport readCounters(const gpu::Buffer& counters);

  const gpu::Context& context_;
  BvhStats stats_;
  gpu::Buffer nodes_;
  gpu::Buffer triangles_;
  gpu::Buffer counters_;      // BVH_COUNTER_WORDS uint: rays, node visits, triangle tests (64-bit each)
  gpu::Buffer raysCounters_;  // the same for traceRays, so it never disturbs a recorded trace
  gpu::ComputePipeline tracePipeline_;
  gpu::ComputePipeline raysPipeline_;
  std::optional<gpu::Buffer> queries_;  // traceRays staging, grown on demand
  std::optional<gpu::Buffer> hits_;
  TraceReport raysReport_;
};

}  // namespace penumbra
