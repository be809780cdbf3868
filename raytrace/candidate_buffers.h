// The candidate line space's GPU buffers (shared/candidates.h): boxes, bits, offsets, packed
// candidates and the per-node map of the hierarchy that uses them, uploaded once and bound at a
// kernel's CS_BINDING_* numbers. Shared by the BVH variant (CandidateTracer, the default
// bindings) and the N-tree variant (NTreeCandidateTracer, kNTreeCandidateBindings).
#pragma once
#include <cstdint>
#include <span>

#include "gpu/pipeline.h"
#include "raytrace/candidate_line_space.h"

namespace penumbra {

// Where a kernel reads the buffers: the CS_BINDING_* defaults, or kNTreeCandidateBindings.
struct CandidateBindings {
  std::uint32_t boxes = CS_BINDING_BOXES, bits = CS_BINDING_BITS, offsets = CS_BINDING_OFFSETS,
                nodeMap = CS_BINDING_NODE_MAP;
};
inline constexpr CandidateBindings kNTreeCandidateBindings{CS_NTREE_BINDING_BOXES, CS_NTREE_BINDING_BITS,
                                                           CS_NTREE_BINDING_OFFSETS, CS_NTREE_BINDING_NODE_MAP};

class CandidateBuffers {
 public:

  // nodeMap: per node of the hierarchy its line space's index, or CS_NONE.
  CandidateBuffers(const gpu::Context& context, const CandidateLineSpace& lineSpace,
                   std::span<const std::uint32_t> nodeMap, CandidateBindings bindings = {});

  gpu::Descriptors& addBindings(gpu::Descriptors& descriptors) const;
  // The packed candidates' device address, for CsParams::candidates (read through it, not bound).
  glm::uvec2 candidatesAddress() const { return gpu::addressHalves(candidates_); }
  std::uint64_t bytes() const;

 private:
  CandidateBindings at_;
  gpu::Buffer boxes_, bits_, offsets_, candidates_, nodeMap_;
};

}  // namespace penumbra
