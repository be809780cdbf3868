#include "raytrace/candidate_tracer.h"

#include <cmath>
#include <cstring>

#include "candidate_rays_comp.h"
#include "raytrace/bvh_tracer.h"
#include "gpu/upload.h"
#include "raytrace/scene_triangles.h"

namespace penumbra {
namespace {

constexpr gpu::Binding kBindings[] = {{BVH_BINDING_COUNTERS, vk::DescriptorType::eStorageBuffer},
                                      {BVH_BINDING_QUERIES, vk::DescriptorType::eStorageBuffer},
                                      {BVH_BINDING_HITS, vk::DescriptorType::eStorageBuffer},
                                      {CS_BINDING_BOXES, vk::DescriptorType::eStorageBuffer},
                                      {CS_BINDING_BITS, vk::DescriptorType::eStorageBuffer},
                                      {CS_BINDING_OFFSETS, vk::DescriptorType::eStorageBuffer},
                                      {CS_BINDING_NODE_MAP, vk::DescriptorType::eStorageBuffer}};

constexpr vk::DeviceSize kCounterBytes = BVH_COUNTER_WORDS * sizeof(std::uint32_t);
constexpr auto kStorage = vk::BufferUsageFlagBits::eStorageBuffer;

Bvh buildBvh(const gpu::Context& context, const Scene& scene, const CandidateTracerSettings& settings) {
  context.requireSubgroupArithmetic("CandidateTracer");
  return BvhBuilder(settings.bvh).build(scene, MeshSet::All);
}

}  // namespace

CandidateTracer::CandidateTracer(const gpu::Context& context, const Scene& scene, const CandidateTracerSettings& settings)
    : CandidateTracer(context, scene, buildBvh(context, scene, settings), BvhLineSpaceNodes{}, settings) {}

CandidateTracer::CandidateTracer(const gpu::Context& context, const Scene& scene, std::span<const CandidateBox> boxes,
                                 const CandidateTracerSettings& settings)
    : CandidateTracer(context, scene, buildBvh(context, scene, settings),
                      BvhLineSpaceNodes{std::vector<CandidateBox>(boxes.begin(), boxes.end()), {}}, settings) {}

// `placed` without a node map: place at settings.depth unless it holds boxes (then no node uses them).
CandidateTracer::CandidateTracer(const gpu::Context& context, const Scene& scene, Bvh bvh, BvhLineSpaceNodes placed,
                                 const CandidateTracerSettings& settings)
    : context_(context),
      bvh_(std::move(bvh)),
      nodeMap_(placed.boxes.empty() ? bvhNodesAtDepth(bvh_, settings.depth).nodeMap
                                    : std::vector<std::uint32_t>(bvh_.nodes.size(), CS_NONE)),
      lineSpace_(buildCandidateLineSpace(scene,
                                         placed.boxes.empty() ? bvhNodesAtDepth(bvh_, settings.depth).boxes : placed.boxes,
                                         CandidateSettings{settings.n, settings.budgetBytes, false, context.maxBufferBytes()},
                                         context.storageBufferRange())),
      maxDeviationDeg_(settings.maxNormalDeviationDeg),
      nodes_(gpu::uploadedBuffer(context, std::span(bvh_.nodes), vk::BufferUsageFlagBits::eShaderDeviceAddress,
                                 "candidate bvh nodes")),
      triangles_(gpu::uploadedBuffer(context, std::span(bvh_.triangles), vk::BufferUsageFlagBits::eShaderDeviceAddress,
                          "candidate bvh triangles")),
      cutouts_(context, scene),
      buffers_(context, lineSpace_, nodeMap_),
      sceneTriangles_(gpu::uploadedBuffer(context, std::span<const shared::SceneTriangle>(sceneTriangles(scene)),
                                          vk::BufferUsageFlagBits::eShaderDeviceAddress, "candidate scene triangles")),
      counters_(context, kCounterBytes, kStorage, "candidate counters"),
      pipeline_(context, candidate_rays_comp, kBindings, sizeof(shared::CsRaysPush), "candidate rays pipeline"),
      rayBatches_(context, "candidates") {}

shared::CsParams CandidateTracer::params() const {
  const float cosMax = maxDeviationDeg_ >= 180.0f ? -2.0f : std::cos(glm::radians(maxDeviationDeg_));
  return shared::CsParams{lineSpace_.n, cosMax, buffers_.candidatesAddress(), gpu::addressHalves(sceneTriangles_), 0u, 0u};
}

shared::BvhAddresses CandidateTracer::bvhAddresses() const {
  return cutouts_.with({gpu::addressHalves(nodes_), gpu::addressHalves(triangles_), {}, {}});
}

gpu::Descriptors& CandidateTracer::addBindings(gpu::Descriptors& descriptors) const {
  return buffers_.addBindings(descriptors);
}

std::uint64_t CandidateTracer::bytes() const {
  return nodes_.size() + triangles_.size() + cutouts_.bytes() + buffers_.bytes() + sceneTriangles_.size();
}

std::vector<shared::RayHit> CandidateTracer::traceRays(std::span<const shared::RayQuery> rays, bool useLineSpace) {
  return trace(rays, useLineSpace ? CS_MODE_BVH_LS : CS_MODE_BVH_EXACT, 0u);
}

std::vector<shared::RayHit> CandidateTracer::traceBox(std::span<const shared::RayQuery> rays, std::uint32_t box) {
  if (box >= lineSpace_.boxes.size()) throw std::invalid_argument("CandidateTracer::traceBox: no line space " + std::to_string(box));
  return trace(rays, CS_MODE_BOX, box);
}

std::vector<shared::RayHit> CandidateTracer::trace(std::span<const shared::RayQuery> rays, std::uint32_t mode,
                                                   std::uint32_t box) {
  std::memset(counters_.data(), 0, kCounterBytes);  // no GPU work is in flight between submissions
  auto out = rayBatches_.trace(rays, BVH_GROUP_SIZE, [&](const vk::raii::CommandBuffer& cmd, const gpu::Buffer& queries,
                                                         const gpu::Buffer& hits, std::uint32_t first, std::uint32_t count) {
    gpu::Descriptors descriptors;
    descriptors.buffer(BVH_BINDING_COUNTERS, counters_)
        .buffer(BVH_BINDING_QUERIES, queries)
        .buffer(BVH_BINDING_HITS, hits);
    pipeline_.bind(cmd, addBindings(descriptors));
    pipeline_.pushConstants(cmd, shared::CsRaysPush{bvhAddresses(), params(), first, count, mode, box});
    cmd.dispatch((count + BVH_GROUP_SIZE - 1) / BVH_GROUP_SIZE, 1, 1);
  });
  report_.trace = BvhTracer::readCounters(counters_);
  const auto words = counters_.download<std::uint32_t>(BVH_COUNTER_WORDS);
  report_.candidateTests =
      std::uint64_t(words[CS_COUNTER_CANDIDATE_TESTS]) | (std::uint64_t(words[CS_COUNTER_CANDIDATE_TESTS + 1]) << 32);
  return out;
}

}  // namespace penumbra
