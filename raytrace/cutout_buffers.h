// The cut-out triangles and texture alpha (core/cutouts.h) uploaded for the GPU BVH's kernels,
// which read them through BvhAddresses::cutouts and ::cutoutTexels when a candidate hit lies on a
// cut-out triangle, and for the ray queries' and the line space's (SceneAccelerationStructures,
// LineSpaceTracer). A scene without cut-outs holds one unused word in each.
#pragma once
#include <cstdint>

#include "core/cutouts.h"
#include "gpu/resources.h"
#include "shared/bvh.h"

namespace penumbra {

class CutoutBuffers {
 public:
  CutoutBuffers(const gpu::Context& context, const Scene& scene);
  // `bvh` with the cut-out addresses filled in.
  shared::BvhAddresses with(shared::BvhAddresses bvh) const;
  // The CutoutTriangles' and the alpha words' addresses, as (low, high).
  glm::uvec2 trianglesAddress() const { return gpu::addressHalves(triangles_); }
  glm::uvec2 texelsAddress() const { return gpu::addressHalves(texels_); }
  std::uint64_t bytes() const { return triangles_.size() + texels_.size(); }

 private:
  CutoutBuffers(const gpu::Context& context, const CutoutData& data);
  gpu::Buffer triangles_;
  gpu::Buffer texels_;
};

}  // namespace penumbra
