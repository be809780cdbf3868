// The N-tree with candidate line spaces (Keul et al. 2018, 3.2 "Adaptation to NTree", the paper's
// NTree(N, d) + LS(D)): one N-tree over the static meshes carries the binary line space
// (LineSpaceTracer, binary mode: the bits skip empty shafts, and shadow rays ask them) and
// candidate line spaces (CandidateBuffers) at its subdivided nodes at level D and at shallower
// nodes with fewer than T triangles (boxesAtDepth); a kernel (indirect_ntree_ls.comp) answers a
// ray at those nodes by csHit, as at leaves. The moving meshes stay on the line-space tracer's
// dynamic BVH. LineSpace node-pool indices are the N-tree's node indices (buildLineSpace keeps
// them), so the node map is indexed by either.
#pragma once
#include <cstdint>
#include <memory>

#include "raytrace/candidate_buffers.h"
#include "raytrace/linespace_tracer.h"

namespace penumbra {

struct NTreeCandidateSettings {
  static constexpr std::uint32_t kSecondToLast = 0xffffffffu;  // D = d - 1, the paper's NTree(6,3)+LS(2)
  LineSpaceSettings lineSpace;        // N, d, budget (binary shadows and the moving meshes' BVH are forced)
  // D, the level of the nodes that get a candidate line space; kSecondToLast: d - 1, or the deepest
  // level whose worst case fits the budget and the device's per-buffer limit.
  std::uint32_t depth = kSecondToLast;
  std::uint32_t minTriangles = 8;     // T: shallower nodes with fewer triangles get one too (0: none)
  float maxNormalDeviationDeg = 30.0f;  // CandidateTracerSettings::maxNormalDeviationDeg
};

class NTreeCandidateTracer {
 public:
  // Throws InputError for bad (N, d) or D, a scene without static triangles, or when the binary
  // pools and the candidate line spaces' worst case together exceed the budget (before any bit is
  // computed or ray cast), or a buffer exceeds the device's maxStorageBufferRange.
  NTreeCandidateTracer(const gpu::Context& context, const Scene& scene, const NTreeCandidateSettings& settings);

  std::uint32_t depth() const { return depth_; }  // D as placed
  // The default D (d - 1) did not fit the budget or the device's buffers: depth() is shallower.
  bool placedShallower() const { return shallower_; }
  const LineSpaceTracer& lineSpace() const { return *lineSpace_; }
  const CandidateLineSpace& candidates() const { return candidates_; }
  const std::vector<std::uint32_t>& nodeMap() const { return nodeMap_; }
  // For the kernel: its push-constant parts and every buffer (line space, dynamic BVH, candidates).
  const shared::LsPush& push() const { return lineSpace_->push(); }
  shared::CsParams params() const;
  gpu::Descriptors& addBindings(gpu::Descriptors& descriptors) const;
  std::uint64_t bytes() const { return lineSpace_->stats().bytes + buffers_->bytes(); }
  double buildMs() const { return lineSpace_->stats().buildMs + candidates_.stats.buildMs; }
  // The moving meshes moved: refits their BVH; the static structures stay.
  BvhRefitReport update(const Scene& scene) { return lineSpace_->update(scene); }

 private:
  std::uint32_t depth_ = 0;
  bool shallower_ = false;
  float maxDeviationDeg_;
  std::vector<std::uint32_t> nodeMap_;
  std::unique_ptr<LineSpaceTracer> lineSpace_;
  CandidateLineSpace candidates_;
  std::unique_ptr<CandidateBuffers> buffers_;
};

}  // namespace penumbra
