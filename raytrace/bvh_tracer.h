// The GPU BVH tracer: the scene's BVH (BvhBuilder) in two storage buffers, shadow rays for a
// TraceJob by an indirect dispatch of bvh_trace.comp, and arbitrary rays through bvh_rays.comp.
// Scenes with moving meshes get two trees in those buffers (shared/bvh.h): the static meshes'
// (root 0, built once and never touched again) and the dynamic meshes' right after it, refit or
// rebuilt by update() (raytrace/bvh_refit.h) in room sized for any rebuild, so nothing reallocates.
#pragma once
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gpu/pipeline.h"
#include "raytrace/bvh_builder.h"
#include "raytrace/bvh_refit.h"
#include "raytrace/cutout_buffers.h"
#include "raytrace/ray_batches.h"
#include "raytrace/shadow_tracer.h"

namespace penumbra {

class BvhTracer final : public ShadowTracer {
 public:
  // Builds and uploads the BVH. Throws InputError when the scene is empty or its BVH would not fit
  // one buffer of this device (maxMemoryAllocationSize; 2 GiB on lavapipe: the kernels read it
  // through its device address, so one binding's 128 MiB range does not limit it), and
  // std::runtime_error when the device lacks subgroup arithmetic in compute shaders.
  BvhTracer(const gpu::Context& context, const Scene& scene, const BvhBuildSettings& settings = {});

  std::string name() const override { return "bvh"; }
  bool onDevice() const override { return true; }
  // Resets the counters and records the indirect trace; its barriers order it after the compute
  // pass that wrote job.points / job.count and before later compute passes and host reads.
  void record(const vk::raii::CommandBuffer& cmd, const TraceJob& job) override;
  TraceReport finish(const TraceJob& job) override;  // the counters of the last record() (each resets them)

  // Both trees: nodes, leaves, triangles, bytes (as allocated) and buildMs summed; sahCost and
  // maxDepth are the static tree's. The dynamic tree alone: dynamicBvh().bvh().stats.
  const BvhStats& stats() const { return stats_; }
  const DynamicBvh& dynamicBvh() const { return dynamic_; }
  // Node index of the dynamic tree's root (BVH_NO_TREE without dynamic meshes); the static tree
  // fills nodes [0, dynamicRoot()) and triangles [0, staticTriangles()).
  std::uint32_t dynamicRoot() const { return dynamicRoot_; }
  std::uint32_t staticTriangles() const { return staticTriangles_; }

  // The scene's dynamic meshes moved (same scene, same triangles): refits the dynamic tree, or
  // rebuilds it when its SAH cost grew past BvhBuildSettings::rebuildGrowth, and rewrites only the
  // dynamic part of both buffers. A no-op without dynamic meshes. Call it between frames (no
  // submission may read the buffers). Throws InputError when the dynamic meshes changed size.
  BvhRefitReport update(const Scene& scene);
  std::optional<BvhRefitReport> sceneMoved(const Scene& scene) override { return update(scene); }
  // The uploaded BVH, host visible (for the bandwidth model): BvhNode and BvhTriangle arrays.
  const gpu::Buffer& nodeBuffer() const { return nodes_; }
  const gpu::Buffer& triangleBuffer() const { return triangles_; }

  // Traces `rays` now (own submissions, waits). anyHit: each hit is the first one found, not
  // necessarily the nearest; closest-hit otherwise. A miss has t < 0 and triangle BVH_NO_HIT.
  std::vector<shared::RayHit> traceRays(std::span<const shared::RayQuery> rays, bool anyHit);
  // Rays, node visits and triangle tests of the last traceRays call.
  const TraceReport& lastRaysReport() const { return raysReport_; }
  // Rays, node visits and triangle tests from a counter buffer of BVH_COUNTER_WORDS (shared/bvh.h).
  static TraceReport readCounters(const gpu::Buffer& counters);
  // What a kernel including bvh_traverse.glsl through addresses needs: both trees' buffers and the dynamic root.
  shared::BvhTracePush tracePush() const { return {addresses(), dynamicRoot_, 0u, 0u, 0u}; }

 private:
  shared::BvhAddresses addresses() const;
  BvhTracer(const gpu::Context& context, const Scene& scene, Bvh staticBvh, const BvhBuildSettings& settings);

  const gpu::Context& context_;
  BvhStats stats_;
  DynamicBvh dynamic_;
  std::uint32_t dynamicRoot_ = BVH_NO_TREE;
  std::uint32_t staticTriangles_ = 0;
  gpu::Buffer nodes_;
  gpu::Buffer triangles_;
  CutoutBuffers cutouts_;
  gpu::Buffer counters_;      // BVH_COUNTER_WORDS uint: rays, node visits, triangle tests (64-bit each)
  gpu::Buffer raysCounters_;  // the same for traceRays, so it never disturbs a recorded trace
  gpu::ComputePipeline tracePipeline_;
  gpu::ComputePipeline raysPipeline_;
  RayBatches rayBatches_;  // traceRays staging
  TraceReport raysReport_;
};

}  // namespace penumbra
