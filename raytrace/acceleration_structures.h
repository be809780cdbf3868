// Driver-built acceleration structures over a scene (VK_KHR_acceleration_structure), for the
// ray-query tracer: one compacted bottom-level structure per static mesh, packed in one buffer
// (opaque geometry, except cut-out meshes, whose candidates the shaders test: rq_common.glsl);
// one per moving mesh, built to allow updates; and a top-level structure over all of them
// (identity instances: scene positions are world space). Each mesh's triangles go to the driver in
// Morton order of their centroids: Mesa 25.0's lavapipe builds trees whose quality follows the input
// order (the Stanford Bunny in its file's order traced ~70x slower than sorted), and a builder that
// sorts anyway loses nothing.
// Moving meshes keep their triangle counts (core/scene.h); update() refits their structures in
// place, or rebuilds them when refitting has degraded the tree: the decision is DynamicBvh's
// (raytrace/bvh_refit.h), the SAH growth of the same refit on the project's own tree, since a
// driver's refit keeps its topology in the same way and reports no cost of its own.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/scene.h"
#include "gpu/resources.h"
#include "raytrace/bvh_builder.h"
#include "raytrace/bvh_refit.h"
#include "raytrace/cutout_buffers.h"

namespace penumbra {

struct AccelerationStats {
  std::uint32_t bottomLevels = 0;     // one per mesh with triangles
  std::uint64_t bytes = 0;            // structures as kept (static ones compacted) + instances
  std::uint64_t uncompactedBytes = 0; // the static structures before compaction
  std::uint64_t scratchBytes = 0;     // largest scratch a build needed (freed after building)
  double buildMs = 0.0;               // everything, wall clock: uploads, builds, compaction, top level
};

// The exact tracer "auto" stands for on this device: "rq" on a GPU with ray queries (its ray-tracing
// hardware), "bvh" elsewhere: on a CPU device (lavapipe) the compute BVH traces more rays/s than the
// driver's structures (bench/results/tracers.md).
std::string defaultTracer(const gpu::Context& context);

class SceneAccelerationStructures {
 public:
  // Builds over the meshes in `set` (the line space traces its moving meshes with MeshSet::Dynamic).
  // Throws InputError for a selection without triangles or a device without ray queries
  // (gpu::Context::requireRayQuery).
  SceneAccelerationStructures(const gpu::Context& context, const Scene& scene, const BvhBuildSettings& settings = {},
                              MeshSet set = MeshSet::All);
  SceneAccelerationStructures(const SceneAccelerationStructures&) = delete;
  SceneAccelerationStructures& operator=(const SceneAccelerationStructures&) = delete;

  vk::AccelerationStructureKHR top() const { return *top_; }
  const AccelerationStats& stats() const { return stats_; }
  // Scene-order triangle ids (BvhTriangle::id) of the build order, after the cut-outs' addresses
  // and two uints per instance (shared/ray_query.h): a hit's id =
  // ids[ids[RQ_IDS_INSTANCES + 2 instance] + primitive index].
  const gpu::Buffer& triangleIds() const { return *triangleIds_; }

  // The moving meshes were posed anew: uploads their vertices, refits their structures (or
  // rebuilds them, see above) and rebuilds the top level. A no-op without moving meshes. Call it
  // between frames. ms counts everything, the decision's CPU refit included.
  BvhRefitReport update(const Scene& scene);

  // Orders this object's builds before compute shaders that trace the top level.
  static void recordBuildToTrace(const vk::raii::CommandBuffer& cmd);

 private:
  struct Moving {  // one moving mesh's structure and the inputs it is refit from
    std::size_t mesh;
    std::uint32_t triangles;
    bool opaque;  // not a cut-out
    gpu::Buffer vertices, indices, storage;
    vk::raii::AccelerationStructureKHR structure{nullptr};
  };
  void buildStatic(const Scene& scene, MeshSet set);
  void buildMoving(const Scene& scene, MeshSet set);
  void buildTop(const vk::raii::CommandBuffer& cmd, bool update);
  void recordMoving(const vk::raii::CommandBuffer& cmd, Moving& m, bool update);
  vk::DeviceAddress scratch(vk::DeviceSize bytes);  // aligned address in a scratch buffer of at least `bytes`

  const gpu::Context& context_;
  CutoutBuffers cutouts_;  // cut-out meshes are non-opaque geometry, tested in the shaders' candidate loop
  AccelerationStats stats_;
  DynamicBvh policy_;
  std::vector<vk::DeviceAddress> instanceTargets_;  // per mesh: its structure's device address (0: no triangles)
  std::optional<gpu::Buffer> staticStorage_;        // the compacted static structures, 256-byte aligned
  std::vector<vk::raii::AccelerationStructureKHR> static_;
  std::vector<Moving> moving_;
  std::vector<std::vector<std::uint32_t>> order_;  // per mesh: its triangles in build order (while building)
  std::optional<gpu::Buffer> triangleIds_;
  std::optional<gpu::Buffer> instances_, topStorage_, scratch_;
  vk::DeviceSize scratchAlignment_ = 0;  // minAccelerationStructureScratchOffsetAlignment, on first use
  vk::raii::AccelerationStructureKHR top_{nullptr};
};

}  // namespace penumbra
