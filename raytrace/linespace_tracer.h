// The line-space tracer (Keul et al. 2017): the binary line space of the scene's N-tree
// (raytrace/line_space) in three storage buffers, shadow rays for a TraceJob by an indirect
// dispatch of linespace_trace.comp. Binary mode (the paper's) stores and tests no geometry: a ray
// is occluded when the shaft it runs through at the second-to-last level meets a non-empty cell,
// so shadows are conservative (slightly too dark), except that the finest node holding the ray's
// start casts no shadow on it (the paper's start-node skip). Exact mode
// (LineSpaceSettings::shadows, linespace_trace_exact.comp) follows set bits down to the leaf cells
// and tests their triangles as the BVH does, so it answers as the BVH; the bits only skip empty
// shafts.
// Two-level for moving geometry: the line space covers the static meshes only (built once); the
// dynamic meshes get their own BVH (DynamicBvh, refit or rebuilt by update()), or with
// LineSpaceSettings::movingTracer "rq" the driver's acceleration structures over them, which the
// same kernel traces exactly for every ray the line space leaves unoccluded.
#pragma once
#include <memory>
#include <string>

#include "gpu/pipeline.h"
#include "raytrace/bvh_refit.h"
#include "raytrace/acceleration_structures.h"
#include "raytrace/cutout_buffers.h"
#include "raytrace/line_space.h"
#include "raytrace/shadow_tracer.h"

namespace penumbra {

class LineSpaceTracer final : public ShadowTracer {
 public:
  // Builds and uploads the line space (static meshes) and the dynamic BVH. Throws InputError for
  // bad (N, d), a scene without static triangles, or pools (with the dynamic BVH) over the budget
  // or over the device's maxStorageBufferRange (128 MiB on lavapipe), and std::runtime_error when
  // the device lacks subgroup arithmetic in compute shaders.
  LineSpaceTracer(const gpu::Context& context, const Scene& scene, const LineSpaceSettings& settings = {});
  // The same on an N-tree built already over the scene's static meshes (NTreeCandidateTracer
  // places its candidate line spaces on it).
  LineSpaceTracer(const gpu::Context& context, const Scene& scene, const NTree& tree, const LineSpaceSettings& settings);

  std::string name() const override { return "ls"; }
  bool onDevice() const override { return true; }
  // Resets the counters and records the indirect trace, with the same barriers as BvhTracer.
  void record(const vk::raii::CommandBuffer& cmd, const TraceJob& job) override;
  // Rays, node visits and triangle tests (exact mode's leaf triangles and the dynamic BVH's) of
  // the last record().
  TraceReport finish(const TraceJob& job) override;

  const LineSpaceStats& stats() const { return stats_; }
  bool exact() const { return exact_; }

  // For kernels of their own (indirect rays): the push constants linespace_traverse.glsl reads, and
  // the pools (exact mode: with the leaf records, lists and triangles) and the moving meshes' BVH
  // added at LS_BINDING_* (no counters). Needs the moving meshes on the BVH (movingTracer Bvh, or
  // Auto where that picks it): std::logic_error with ray queries.
  const shared::LsPush& push() const { return push_; }
  gpu::Descriptors& addBindings(gpu::Descriptors& descriptors) const;
  const DynamicBvh& dynamicBvh() const { return dynamic_; }
  // The moving meshes' acceleration structures when they are traced with ray queries, else null.
  const SceneAccelerationStructures* movingStructures() const { return moving_.get(); }

  // The scene's dynamic meshes moved: refits (or rebuilds) their BVH and rewrites it; the line
  // space is not touched. A no-op without dynamic meshes; call it between frames.
  BvhRefitReport update(const Scene& scene);
  std::optional<BvhRefitReport> sceneMoved(const Scene& scene) override { return update(scene); }

 private:
  LineSpaceTracer(const gpu::Context& context, const Scene& scene, LineSpace lineSpace,
                  const LineSpaceSettings& settings);
  void addPools(gpu::Descriptors& descriptors) const;

  LineSpaceStats stats_;
  bool exact_;
  DynamicBvh dynamic_;
  shared::LsPush push_{};
  CutoutBuffers cutouts_;  // exact mode and the moving meshes' BVH test them (push_.cutouts)
  gpu::Buffer tree_;
  gpu::Buffer nodes_;
  gpu::Buffer bits_;
  gpu::Buffer counters_;  // LS_COUNTER_WORDS uint
  // Exact mode only (null in binary mode): leaf records, leaf triangle lists, triangles.
  std::unique_ptr<gpu::Buffer> leaves_, leafTriangles_, triangles_;
  // The dynamic BVH: node 0 unused (index 0 marks an empty slot), its root at node 1.
  gpu::Buffer bvhNodes_;
  gpu::Buffer bvhTriangles_;
  std::unique_ptr<SceneAccelerationStructures> moving_;  // movingTracer "rq": used instead of the BVH buffers
  gpu::ComputePipeline pipeline_;
};

}  // namespace penumbra
