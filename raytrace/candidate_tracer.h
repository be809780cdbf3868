// The BVH with candidate line spaces (Keul et al. 2018, 3.2) on the GPU: builds the scene's BVH,
// the line spaces of its inner nodes at depth D (or of boxes the caller gives), uploads them with
// the scene's triangles (shared/scene_triangles.h), and traces arbitrary closest-hit rays through
// candidate_rays.comp. A kernel of its own (ambient occlusion, indirect light) includes
// bvh_ls_traverse.glsl or candidate_lookup.glsl, puts params() in its push constants, binds the
// buffers with addBindings() and reads the BVH through bvhAddresses().
#pragma once
#include <optional>
#include <span>
#include <vector>

#include "gpu/pipeline.h"
#include "raytrace/candidate_buffers.h"
#include "raytrace/candidate_line_space.h"
#include "raytrace/cutout_buffers.h"
#include "raytrace/ray_batches.h"
#include "raytrace/shadow_tracer.h"

namespace penumbra {

struct CandidateTracerSettings {
  std::uint32_t n = 6;                 // line-space resolution N
  std::uint32_t depth = 8;             // BVH depth D of the nodes that get a line space (root 0)
  float maxNormalDeviationDeg = 30.0f;  // a candidate's plane hit is dropped where the extrapolated
                                        // normal leans more than this from its face normal; 180 keeps all
  std::uint64_t budgetBytes = 0;       // CandidateSettings::budgetBytes
  BvhBuildSettings bvh;
};

struct CandidateRaysReport {
  TraceReport trace;                  // rays, node visits, exact triangle tests
  std::uint64_t candidateTests = 0;   // candidate planes tested
};

class CandidateTracer {
 public:
  // BVH over all meshes and line spaces at its inner nodes at depth settings.depth. Throws
  // InputError when the scene is empty, or the line spaces exceed the budget or the device's
  // maxStorageBufferRange (before building them); std::runtime_error without subgroup arithmetic.
  CandidateTracer(const gpu::Context& context, const Scene& scene, const CandidateTracerSettings& settings);
  // The same BVH, but line spaces on `boxes` instead (no BVH node uses them: the BVH modes are exact,
  // traceBox asks one of them); for tests. An empty `boxes` means the placement at settings.depth.
  CandidateTracer(const gpu::Context& context, const Scene& scene, std::span<const CandidateBox> boxes,
                  const CandidateTracerSettings& settings);

  // Closest hits now (own submissions, waits): through the line-space nodes, or the exact BVH.
  // RayHit.pad0: packed shading normal facing the origin; pad1: CS_HIT_* flags (shared/candidates.h).
  std::vector<shared::RayHit> traceRays(std::span<const shared::RayQuery> rays, bool useLineSpace = true);
  // Each ray against line space `box` alone (csHit).
  std::vector<shared::RayHit> traceBox(std::span<const shared::RayQuery> rays, std::uint32_t box);
  const CandidateRaysReport& lastRaysReport() const { return report_; }

  const Bvh& bvh() const { return bvh_; }
  const CandidateLineSpace& lineSpace() const { return lineSpace_; }
  const std::vector<std::uint32_t>& nodeMap() const { return nodeMap_; }
  // For kernels of their own: the push-constant part csHit reads, the BVH's addresses, and the
  // CS_BINDING_* buffers added to a descriptor set.
  shared::CsParams params() const;
  shared::BvhAddresses bvhAddresses() const;
  gpu::Descriptors& addBindings(gpu::Descriptors& descriptors) const;
  void setMaxNormalDeviation(float degrees) { maxDeviationDeg_ = degrees; }
  std::uint64_t bytes() const;  // everything uploaded: BVH, line spaces, node map, scene triangles

 private:
  CandidateTracer(const gpu::Context& context, const Scene& scene, Bvh bvh, BvhLineSpaceNodes placed,
                  const CandidateTracerSettings& settings);
  std::vector<shared::RayHit> trace(std::span<const shared::RayQuery> rays, std::uint32_t mode, std::uint32_t box);

  const gpu::Context& context_;
  Bvh bvh_;
  std::vector<std::uint32_t> nodeMap_;
  CandidateLineSpace lineSpace_;
  float maxDeviationDeg_;
  gpu::Buffer nodes_, triangles_;
  CutoutBuffers cutouts_;
  CandidateBuffers buffers_;
  gpu::Buffer sceneTriangles_;
  gpu::Buffer counters_;
  gpu::ComputePipeline pipeline_;
  RayBatches rayBatches_;
  CandidateRaysReport report_;
};

}  // namespace penumbra
