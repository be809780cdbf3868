#include "raytrace/ntree_candidate_tracer.h"

#include <cmath>
#include <cstdio>

#include "core/units.h"

namespace penumbra {
NTreeCandidateTracer::NTreeCandidateTracer(const gpu::Context& context, const Scene& scene,
                                           const NTreeCandidateSettings& settings)
    : maxDeviationDeg_(settings.maxNormalDeviationDeg) {
  context.requireSubgroupArithmetic("NTreeCandidateTracer");
  LineSpaceSettings ls = settings.lineSpace;
  ls.shadows = LineSpaceSettings::Shadows::Binary;
  ls.movingTracer = LineSpaceSettings::Moving::Bvh;
  NTreeBuilder::validate(ls.n, ls.depth);
  const NTree tree = NTreeBuilder(ls.n, ls.depth).build(scene, MeshSet::Static);
  const std::uint64_t groups = tree.nodes.size() - tree.stats.nodesPerLevel[ls.depth - 1];
  const std::uint64_t pools = lineSpaceSizes(ls.n, tree.nodes.size(), groups).total();
  const std::uint64_t budget = ls.budgetBytes ? ls.budgetBytes : defaultLineSpaceBudget();
  // The default D is d - 1 where its worst case fits the budget and the device's per-buffer limit,
  // else the deepest level that does (many small nodes at d - 1 can need more than either).
  const bool defaultDepth = settings.depth == NTreeCandidateSettings::kSecondToLast;
  depth_ = defaultDepth ? ls.depth - 1 : settings.depth;
  std::vector<CandidateBox> boxes = boxesAtDepth(tree, depth_, settings.minTriangles);
  auto fits = [&](std::uint64_t count) {
    const CandidateSizes sizes = candidateWorstCaseSizes(ls.n, count);
    return pools + sizes.total() <= budget && sizes.candidateBytes <= context.maxBufferBytes() &&
           std::max(sizes.bitBytes, sizes.offsetBytes) <= context.storageBufferRange();
  };
  while (defaultDepth && depth_ > 0 && !fits(boxes.size())) {
    boxes = boxesAtDepth(tree, --depth_, settings.minTriangles);
    shallower_ = true;
  }

  // Both structures against one budget before either is built.
  const std::uint64_t worst = candidateWorstCaseSizes(ls.n, boxes.size()).total();
  if (pools + worst > budget) {
    throw InputError("N-tree with candidate line spaces (N=" + std::to_string(ls.n) + ", d=" + std::to_string(ls.depth) +
                     ", D=" + std::to_string(depth_) + ") of scene '" + scene.name + "' may need " +
                     megabytes(pools + worst) + " (binary line space " + megabytes(pools) + ", " +
                     std::to_string(boxes.size()) + " candidate line spaces up to " + megabytes(worst) +
                     ") but the budget is " + megabytes(budget) +
                     "; lower N (--linespace-n), d (--linespace-depth) or D (--ntree-ls-depth), or raise "
                     "--linespace-budget (MB)");
  }
  lineSpace_ = std::make_unique<LineSpaceTracer>(context, scene, tree, ls);
  candidates_ = buildCandidateLineSpace(scene, boxes, CandidateSettings{ls.n, budget, false, context.maxBufferBytes()},
                                        context.storageBufferRange(), MeshSet::Static);
  nodeMap_.assign(tree.nodes.size(), CS_NONE);
  for (std::uint32_t i = 0; i < boxes.size(); ++i) nodeMap_[boxes[i].node] = i;
  buffers_ = std::make_unique<CandidateBuffers>(context, candidates_, nodeMap_, kNTreeCandidateBindings);
}

shared::CsParams NTreeCandidateTracer::params() const {
  const float cosMax = maxDeviationDeg_ >= 180.0f ? -2.0f : std::cos(maxDeviationDeg_ * 3.14159265f / 180.0f);
  return shared::CsParams{candidates_.n, cosMax, buffers_->candidatesAddress(), {0u, 0u}, 0u, 0u};
}

gpu::Descriptors& NTreeCandidateTracer::addBindings(gpu::Descriptors& descriptors) const {
  return buffers_->addBindings(lineSpace_->addBindings(descriptors));
}

}  // namespace penumbra
