// The ray-query tracer (--tracer rq): shadow rays answered by inline ray queries (rayQueryEXT) on
// acceleration structures the driver builds (raytrace/acceleration_structures.h), the path that
// uses ray-tracing hardware where a GPU has it. Same kernels' shape, samples, origins and ray ends
// as the BVH tracer (shaders/shadow_rays.glsl); the driver's traversal reports no node visits.
#pragma once
#include <span>
#include <string>
#include <vector>

#include "gpu/pipeline.h"
#include "raytrace/acceleration_structures.h"
#include "raytrace/ray_batches.h"
#include "raytrace/shadow_tracer.h"

namespace penumbra {

class RayQueryTracer final : public ShadowTracer {
 public:
  // Builds the acceleration structures. Throws std::runtime_error when the device lacks ray
  // queries or subgroup arithmetic, InputError for a scene without triangles.
  RayQueryTracer(const gpu::Context& context, const Scene& scene, const BvhBuildSettings& settings = {});

  std::string name() const override { return "rq"; }
  bool onDevice() const override { return true; }
  void record(const vk::raii::CommandBuffer& cmd, const TraceJob& job) override;
  TraceReport finish(const TraceJob& job) override;

  const AccelerationStats& stats() const { return structures_.stats(); }
  // For kernels of their own (rq_common.glsl): the top level and the triangle ids.
  const SceneAccelerationStructures& structures() const { return structures_; }
  // The moving meshes were posed anew: refits (or rebuilds) their structures and the top level.
  BvhRefitReport update(const Scene& scene) { return structures_.update(scene); }
  std::optional<BvhRefitReport> sceneMoved(const Scene& scene) override { return update(scene); }

  // Traces `rays` now, as BvhTracer::traceRays (any-hit or closest-hit; a miss has t < 0).
  std::vector<shared::RayHit> traceRays(std::span<const shared::RayQuery> rays, bool anyHit);

 private:
  SceneAccelerationStructures structures_;
  gpu::Buffer counters_;      // BVH_COUNTER_WORDS: only the rays are counted
  gpu::Buffer raysCounters_;  // the same for traceRays
  gpu::ComputePipeline tracePipeline_;
  gpu::ComputePipeline raysPipeline_;
  RayBatches rayBatches_;
};

}  // namespace penumbra
