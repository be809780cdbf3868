// Keeps a BVH over moving geometry current: refitting rewrites the triangles from the
// scene and recomputes every box bottom-up with the builder's own padding, keeping the topology;
// once refitting has let the SAH cost grow past BvhBuildSettings::rebuildGrowth times the cost
// the tree had when built, the tree is rebuilt with Embree's builder instead. Moving meshes keep
// their triangle count and indices (core/scene.h), so a rebuilt tree has the same triangles.
#pragma once
#include <algorithm>
#include <cstdint>
#include <span>

#include "gpu/resources.h"
#include "raytrace/bvh_builder.h"

namespace penumbra {

// What one update did (also FrameStats::Refit).
struct BvhRefitReport {
  double ms = 0.0;            // refit (or rebuild) and upload, wall clock
  double sah = 0.0;           // SAH cost of the tree now (sahCost)
  double builtSah = 0.0;      // ... when it was last (re)built
  double refitSah = 0.0;      // ... of the refit tree, which decided: above growth limit -> rebuilt
  double growth = 0.0;        // refitSah over the built cost it was compared with (before any rebuild)
  bool rebuilt = false;       // this update rebuilt the tree
  std::uint64_t triangles = 0;  // triangles refit or rebuilt
  std::uint64_t rebuilds = 0;   // rebuilds so far (running count)
};

// Rewrites every triangle of `bvh` from the scene (by its scene-wide id) and recomputes all child
// boxes bottom-up, padded exactly as the builder pads them: refitting an unmoved tree reproduces
// it bit for bit. Topology and depth are unchanged; stats.sahCost is updated. Throws InputError
// when a triangle id is outside the scene or a moved vertex is not finite.
void refitBvh(Bvh& bvh, const Scene& scene);

// The tree over a scene's dynamic meshes and its refit/rebuild policy, shared by the tracers
// that trace moving geometry (BvhTracer, LineSpaceTracer). The tracers own the GPU buffers; this
// class writes the tree into their mapped memory at given offsets.
class DynamicBvh {
 public:
  // Builds over the scene's dynamic meshes (none: empty(), and update() does nothing).
  DynamicBvh(const Scene& scene, const BvhBuildSettings& settings = {});

  bool empty() const { return triangles_ == 0; }
  const Bvh& bvh() const { return bvh_; }
  // Room any rebuild of these triangles needs: a binary tree whose leaves hold one or more of n
  // triangles has at most n - 1 inner nodes (a one-leaf tree still has its root), so the
  // buffers sized for it never grow.
  std::uint64_t nodeCapacity() const { return std::max<std::uint64_t>(1, triangles_); }
  std::uint64_t triangleCount() const { return triangles_; }
  std::uint64_t bytes() const {
    return nodeCapacity() * sizeof(shared::BvhNode) + triangles_ * sizeof(shared::BvhTriangle);
  }

  // Refits to the scene's current positions, or rebuilds when the SAH grew past the threshold, and
  // writes the tree where attach() said (ms counts the write).
  // Throws InputError when the dynamic meshes' triangle counts changed since construction.
  BvhRefitReport update(const Scene& scene);

  // Where the tree lives on the GPU: mapped node and triangle buffers, its root at node
  // `nodeOffset` (not 0, which inner slots use to mark an empty slot) and child indices moved by the
  // offsets. Writes the tree there now, and update() rewrites it there (host-coherent memory: the
  // next submission sees it).
  void attach(const gpu::Buffer& nodes, const gpu::Buffer& triangles, std::uint32_t nodeOffset,
              std::uint32_t triangleOffset);

 private:
  BvhBuildSettings settings_;
  BvhBuilder builder_;
  Bvh bvh_;
  std::uint64_t triangles_ = 0;
  double builtSah_ = 0.0;
  std::uint64_t rebuilds_ = 0;
  const gpu::Buffer* nodes_ = nullptr;  // attach()
  const gpu::Buffer* triangleBuffer_ = nullptr;
  std::uint32_t nodeOffset_ = 0, triangleOffset_ = 0;
  void write() const;
};

}  // namespace penumbra
