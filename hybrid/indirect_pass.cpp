#include "hybrid/indirect_pass.h"

#include <algorithm>

#include "indirect_bvh_comp.h"
#include "indirect_bvh_ls_comp.h"
#include "indirect_ntree_comp.h"
#include "indirect_ntree_ls_comp.h"
#include "indirect_rq_comp.h"
#include "raytrace/scene_triangles.h"
#include "shared/ray_query.h"

namespace penumbra {
namespace {

constexpr vk::DescriptorType kImage = vk::DescriptorType::eStorageImage;
constexpr vk::DescriptorType kBuffer = vk::DescriptorType::eStorageBuffer;
constexpr vk::DescriptorType kSampled = vk::DescriptorType::eCombinedImageSampler;
constexpr gpu::Binding kBindings[] = {
    {INDIRECT_BINDING_POSITION, kImage},  {INDIRECT_BINDING_NORMAL, kImage},          {INDIRECT_BINDING_FRAME, kBuffer},
    {INDIRECT_BINDING_OUTPUT, kBuffer},   {INDIRECT_BINDING_COUNTERS, kBuffer},
    {INDIRECT_BINDING_SHADOW_MAP, kSampled}, {INDIRECT_BINDING_SHADOW_TEXELS, kBuffer}};

// bvh-ls: the candidate line space's buffers.
constexpr gpu::Binding kLsBindings[] = {
    {INDIRECT_BINDING_POSITION, kImage}, {INDIRECT_BINDING_NORMAL, kImage}, {INDIRECT_BINDING_FRAME, kBuffer},
    {INDIRECT_BINDING_OUTPUT, kBuffer},  {INDIRECT_BINDING_COUNTERS, kBuffer}, {INDIRECT_BINDING_SHADOW_MAP, kSampled},
    {INDIRECT_BINDING_SHADOW_TEXELS, kBuffer}, {CS_BINDING_BOXES, kBuffer},
    {CS_BINDING_BITS, kBuffer},          {CS_BINDING_OFFSETS, kBuffer},
    {CS_BINDING_NODE_MAP, kBuffer}};

// rq: the driver's top level and the scene-order triangle ids.
constexpr gpu::Binding kRqBindings[] = {
    {INDIRECT_BINDING_POSITION, kImage},  {INDIRECT_BINDING_NORMAL, kImage},          {INDIRECT_BINDING_FRAME, kBuffer},
    {INDIRECT_BINDING_OUTPUT, kBuffer},   {INDIRECT_BINDING_COUNTERS, kBuffer},
    {INDIRECT_BINDING_SHADOW_MAP, kSampled}, {INDIRECT_BINDING_SHADOW_TEXELS, kBuffer},
    {RQ_BINDING_SCENE, vk::DescriptorType::eAccelerationStructureKHR}, {RQ_BINDING_TRIANGLE_IDS, kBuffer}};

// ntree: the line space's pools in exact mode and the moving meshes' BVH (LineSpaceTracer::addBindings).
constexpr gpu::Binding kNTreeBindings[] = {
    {INDIRECT_BINDING_POSITION, kImage},  {INDIRECT_BINDING_NORMAL, kImage},          {INDIRECT_BINDING_FRAME, kBuffer},
    {INDIRECT_BINDING_OUTPUT, kBuffer},   {INDIRECT_BINDING_COUNTERS, kBuffer},
    {INDIRECT_BINDING_SHADOW_MAP, kSampled}, {INDIRECT_BINDING_SHADOW_TEXELS, kBuffer}, {LS_BINDING_TREE, kBuffer},
    {LS_BINDING_NODES, kBuffer},          {LS_BINDING_BITS, kBuffer},                 {LS_BINDING_BVH_NODES, kBuffer},
    {LS_BINDING_BVH_TRIANGLES, kBuffer},  {LS_BINDING_LEAVES, kBuffer},               {LS_BINDING_LEAF_TRIANGLES, kBuffer},
    {LS_BINDING_TRIANGLES, kBuffer}};

// ntree-ls: the binary pools, the moving meshes' BVH and the candidate buffers (NTreeCandidateTracer).
constexpr gpu::Binding kNTreeLsBindings[] = {
    {INDIRECT_BINDING_POSITION, kImage},  {INDIRECT_BINDING_NORMAL, kImage},          {INDIRECT_BINDING_FRAME, kBuffer},
    {INDIRECT_BINDING_OUTPUT, kBuffer},   {INDIRECT_BINDING_COUNTERS, kBuffer},
    {INDIRECT_BINDING_SHADOW_MAP, kSampled}, {INDIRECT_BINDING_SHADOW_TEXELS, kBuffer}, {LS_BINDING_TREE, kBuffer},
    {LS_BINDING_NODES, kBuffer},          {LS_BINDING_BITS, kBuffer},                 {LS_BINDING_BVH_NODES, kBuffer},
    {LS_BINDING_BVH_TRIANGLES, kBuffer},  {CS_NTREE_BINDING_BOXES, kBuffer},          {CS_NTREE_BINDING_BITS, kBuffer},
    {CS_NTREE_BINDING_OFFSETS, kBuffer},  {CS_NTREE_BINDING_NODE_MAP, kBuffer}};

struct BvhPush {
  shared::IndirectParams params;
  shared::BvhTracePush bvh;
};
struct BvhLsPush {
  shared::IndirectParams params;
  shared::BvhTracePush bvh;
  shared::CsParams cs;
};
struct NTreePush {
  shared::IndirectParams params;
  shared::LsPush ls;
};
struct NTreeLsPush {
  shared::IndirectParams params;
  shared::LsPush ls;
  shared::CsParams cs;
};
static_assert(sizeof(shared::IndirectParams) == 32, "IndirectParams must match std430");

// Read through its address: held to one buffer's size, not one binding's range.
vk::DeviceSize triangleBytes(const gpu::Context& context, const Scene& scene) {
  const vk::DeviceSize bytes = std::max<vk::DeviceSize>(1, scene.triangleCount()) * sizeof(shared::SceneTriangle);
  if (bytes > context.maxBufferBytes()) {
    throw InputError("ao/indirect: the scene's " + std::to_string(scene.triangleCount()) + " triangles need " +
                     std::to_string(bytes >> 20) + " MiB in one buffer, over this device's " +
                     std::to_string(context.maxBufferBytes() >> 20) + " MiB (maxBufferSize, maxMemoryAllocationSize)");
  }
  return bytes;
}

}  // namespace

const Options<IndirectSettings>& indirectOptions() {
  static const Options<IndirectSettings> options = [] {
    using S = IndirectSettings;
    Options<S> o("Indirect light: ao, indirect");
    o.number("--ao-radius", "indirect/ao_radius", &S::aoRadius,
             "Method ao: occlusion radius, fraction of the scene radius", 1e-6f);
    o.number("--indirect-rays", "indirect/rays", &S::rays, "Methods ao and indirect: cosine-weighted rays per pixel", 1u,
             INDIRECT_MAX_RAYS);
    o.choice("--hit-light", "indirect/hit_light", &S::hitShadowMap,
             "Method indirect: a bounce's hit sees the light through a shadow ray (exact) or the light's shadow map "
             "(sm's answer, no ray); the Embree reference always traces the ray",
             {{"shadow-ray", false}, {"shadow-map", true}});
    o.number("--bvh-ls-depth", "indirect/bvh_ls_depth", &S::bvhDepth,
             "Tracer bvh-ls of ao/indirect: candidate line spaces (N = --linespace-n) at the BVH's inner nodes at this "
             "depth (root 0); deeper = closer to exact, more memory",
             0u, 30u);
    o.number("--ntree-ls-depth", "indirect/ntree_ls_depth", &S::ntreeDepth,
             "Tracer ntree-ls of ao/indirect (the paper's NTree(N,d)+LS(D)): candidate line spaces at the N-tree's "
             "(--linespace-n, --linespace-depth) nodes at level D (0..d-1; -1 = d-1) and at shallower nodes with "
             "fewer than --ntree-ls-min-triangles triangles; the bounces' shadow rays use the binary line space. "
             "Tracer ntree: the same N-tree's line space in exact mode (exact closest hits)",
             -1, int(LS_MAX_DEPTH) - 1);
    o.number("--ntree-ls-min-triangles", "indirect/ntree_ls_min_triangles", &S::ntreeMinTriangles,
             "Tracer ntree-ls: shallower N-tree nodes with fewer triangles than this get a line space too (0: none)");
    o.number("--candidate-deviation", "indirect/candidate_deviation_deg", &S::maxDeviationDeg,
             "Candidate line spaces: drop a plane hit whose extrapolated normal leans more than this many degrees from "
             "the candidate's face normal (180 keeps all)",
             0.0f, 180.0f);
    return o;
  }();
  return options;
}

const std::vector<std::string>& indirectTracers() {
  static const std::vector<std::string> names{"bvh", "rq", "bvh-ls", "ntree", "ntree-ls", "embree"};
  return names;
}

bool isIndirectTracer(const std::string& name) {
  return std::find(indirectTracers().begin(), indirectTracers().end(), name) != indirectTracers().end();
}

std::string indirectTracerList() {
  std::string s;
  for (const std::string& n : indirectTracers()) s += (s.empty() ? "" : ", ") + n;
  return s;
}

IndirectPass::IndirectPass(const gpu::Context& context, const Scene& scene)
    : context_(context),
      triangles_(context, triangleBytes(context, scene), vk::BufferUsageFlagBits::eShaderDeviceAddress, "scene triangles"),
      counters_(context, INDIRECT_COUNTER_WORDS * sizeof(std::uint32_t), vk::BufferUsageFlagBits::eStorageBuffer |
                vk::BufferUsageFlagBits::eTransferDst, "indirect counters"),
      bvh_(context, indirect_bvh_comp, kBindings, sizeof(BvhPush), "indirect rays (bvh)"),
      bvhLs_(context, indirect_bvh_ls_comp, kLsBindings, sizeof(BvhLsPush), "indirect rays (bvh-ls)"),
      ntree_(context, indirect_ntree_comp, kNTreeBindings, sizeof(NTreePush), "indirect rays (ntree)"),
      ntreeLs_(context, indirect_ntree_ls_comp, kNTreeLsBindings, sizeof(NTreeLsPush), "indirect rays (ntree-ls)") {
  update(scene);
}

void IndirectPass::update(const Scene& scene) {
  const std::vector<shared::SceneTriangle> triangles = sceneTriangles(scene);
  triangles_.upload(std::span<const shared::SceneTriangle>(triangles));
}

shared::IndirectParams IndirectPass::recordStart(const vk::raii::CommandBuffer& cmd, shared::IndirectParams params) {
  using Stage = vk::PipelineStageFlagBits2;
  using Access = vk::AccessFlagBits2;
  gpu::memoryBarrier(cmd, Stage::eComputeShader, Access::eShaderStorageRead | Access::eShaderStorageWrite,
                     Stage::eTransfer, Access::eTransferWrite);
  cmd.fillBuffer(counters_.handle(), 0, VK_WHOLE_SIZE, 0u);
  gpu::memoryBarrier(cmd, Stage::eTransfer, Access::eTransferWrite, Stage::eComputeShader,
                     Access::eShaderStorageRead | Access::eShaderStorageWrite);
  params.triangles = gpu::addressHalves(triangles_);
  return params;
}

gpu::Descriptors IndirectPass::descriptors(const IndirectTargets& t) const {
  gpu::Descriptors d;
  d.storageImage(INDIRECT_BINDING_POSITION, t.gbuffer.position().view())
      .storageImage(INDIRECT_BINDING_NORMAL, t.gbuffer.normal().view())
      .buffer(INDIRECT_BINDING_FRAME, t.frame)
      .buffer(INDIRECT_BINDING_OUTPUT, t.output)
      .buffer(INDIRECT_BINDING_COUNTERS, counters_)
      .sampledImage(INDIRECT_BINDING_SHADOW_MAP, t.shadowMap.depth().view(), t.shadowMap.sampler())
      .buffer(INDIRECT_BINDING_SHADOW_TEXELS, t.shadowMap.texels());
  return d;
}

void IndirectPass::dispatch(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer) const {
  cmd.dispatch((gbuffer.width() + INDIRECT_GROUP_SIZE - 1) / INDIRECT_GROUP_SIZE,
               (gbuffer.height() + INDIRECT_GROUP_SIZE - 1) / INDIRECT_GROUP_SIZE, 1);
  gpu::computeToComputeAndHost(cmd);
}

// Each kernel's pipeline is specialized on how the light's map is read (light_texels.glsl).
void IndirectPass::record(const vk::raii::CommandBuffer& cmd, const IndirectTargets& targets,
                          const shared::IndirectParams& params, const BvhTracer& bvh) {
  const shared::IndirectParams p = recordStart(cmd, params);
  const gpu::ComputePipeline& pipeline = bvh_(targets.shadowMap.hasTexelCopy());
  pipeline.bind(cmd, descriptors(targets));
  pipeline.pushConstants(cmd, BvhPush{p, bvh.tracePush()});
  dispatch(cmd, targets.gbuffer);
}

void IndirectPass::record(const vk::raii::CommandBuffer& cmd, const IndirectTargets& targets,
                          const shared::IndirectParams& params, const RayQueryTracer& rq) {
  if (!rq_) rq_.emplace(context_, indirect_rq_comp, kRqBindings, sizeof(shared::IndirectParams), "indirect rays (rq)");
  const shared::IndirectParams p = recordStart(cmd, params);
  SceneAccelerationStructures::recordBuildToTrace(cmd);
  const gpu::ComputePipeline& pipeline = (*rq_)(targets.shadowMap.hasTexelCopy());
  gpu::Descriptors d = descriptors(targets);
  d.accelerationStructure(RQ_BINDING_SCENE, rq.structures().top()).buffer(RQ_BINDING_TRIANGLE_IDS, rq.structures().triangleIds());
  pipeline.bind(cmd, d);
  pipeline.pushConstants(cmd, p);
  dispatch(cmd, targets.gbuffer);
}

void IndirectPass::record(const vk::raii::CommandBuffer& cmd, const IndirectTargets& targets,
                          const shared::IndirectParams& params, const CandidateTracer& candidates) {
  const shared::IndirectParams p = recordStart(cmd, params);
  const gpu::ComputePipeline& pipeline = bvhLs_(targets.shadowMap.hasTexelCopy());
  gpu::Descriptors d = descriptors(targets);
  pipeline.bind(cmd, candidates.addBindings(d));
  shared::CsParams cs = candidates.params();
  cs.triangles = p.triangles;  // the candidates' triangles: this pass's copy, as the hits' shading reads them
  pipeline.pushConstants(cmd, BvhLsPush{p, {candidates.bvhAddresses(), BVH_NO_TREE, 0u, 0u, 0u}, cs});
  dispatch(cmd, targets.gbuffer);
}

void IndirectPass::record(const vk::raii::CommandBuffer& cmd, const IndirectTargets& targets,
                          const shared::IndirectParams& params, const LineSpaceTracer& ntree) {
  const shared::IndirectParams p = recordStart(cmd, params);
  const gpu::ComputePipeline& pipeline = ntree_(targets.shadowMap.hasTexelCopy());
  gpu::Descriptors d = descriptors(targets);
  pipeline.bind(cmd, ntree.addBindings(d));
  pipeline.pushConstants(cmd, NTreePush{p, ntree.push()});
  dispatch(cmd, targets.gbuffer);
}

void IndirectPass::record(const vk::raii::CommandBuffer& cmd, const IndirectTargets& targets,
                          const shared::IndirectParams& params, const NTreeCandidateTracer& ntreeLs) {
  const shared::IndirectParams p = recordStart(cmd, params);
  const gpu::ComputePipeline& pipeline = ntreeLs_(targets.shadowMap.hasTexelCopy());
  gpu::Descriptors d = descriptors(targets);
  pipeline.bind(cmd, ntreeLs.addBindings(d));
  shared::CsParams cs = ntreeLs.params();
  cs.triangles = p.triangles;  // the candidates' triangles: this pass's
  pipeline.pushConstants(cmd, NTreeLsPush{p, ntreeLs.push(), cs});
  dispatch(cmd, targets.gbuffer);
}

TraceReport IndirectPass::report(std::uint64_t* shadowRays) const {
  const auto words = counters_.download<std::uint32_t>(INDIRECT_COUNTER_WORDS);
  auto value = [&](std::uint32_t low) { return std::uint64_t(words[low]) | (std::uint64_t(words[low + 1]) << 32); };
  TraceReport r;
  r.rays = value(INDIRECT_COUNTER_RAYS);
  r.nodeVisits = value(INDIRECT_COUNTER_NODE_VISITS);
  r.triangleTests = value(INDIRECT_COUNTER_TESTS);
  if (shadowRays) *shadowRays = value(INDIRECT_COUNTER_SHADOW_RAYS);
  return r;
}

}  // namespace penumbra
