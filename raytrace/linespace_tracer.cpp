#include "raytrace/linespace_tracer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <span>
#include <stdexcept>
#include <vector>

#include "linespace_trace_comp.h"
#include "linespace_trace_exact_comp.h"
#include "linespace_trace_exact_rq_comp.h"
#include "linespace_trace_rq_comp.h"
#include "shared/trace.h"

namespace penumbra {
namespace {


// linespace_trace(_exact)(.comp|_rq.comp): the moving meshes' BVH nodes and triangles, or their
// top level and triangle ids (ray queries); exact mode adds the leaf records, lists and triangles.
std::vector<gpu::Binding> bindings(bool rayQueries, bool exact) {
  const auto storage = vk::DescriptorType::eStorageBuffer;
  std::vector<gpu::Binding> list{
      {{LS_BINDING_TREE, storage},
       {LS_BINDING_NODES, storage},
       {LS_BINDING_BITS, storage},
       {LS_BINDING_COUNTERS, storage},
       {LS_BINDING_TRACE_JOB, storage},
       {LS_BINDING_TRACE_JOB + 1, storage},
       {LS_BINDING_TRACE_JOB + 2, storage},
       {LS_BINDING_BVH_NODES, rayQueries ? vk::DescriptorType::eAccelerationStructureKHR : storage},
       {LS_BINDING_BVH_TRIANGLES, storage},
       {TRACE_BINDING_POSITION, vk::DescriptorType::eStorageImage},
       {TRACE_BINDING_NORMAL, vk::DescriptorType::eStorageImage}}};
  if (exact) {
    list.push_back({LS_BINDING_LEAVES, storage});
    list.push_back({LS_BINDING_LEAF_TRIANGLES, storage});
    list.push_back({LS_BINDING_TRIANGLES, storage});
  }
  return list;
}

std::span<const std::uint32_t> kernel(bool rayQueries, bool exact) {
  if (exact) return rayQueries ? std::span<const std::uint32_t>(linespace_trace_exact_rq_comp) : linespace_trace_exact_comp;
  return rayQueries ? std::span<const std::uint32_t>(linespace_trace_rq_comp) : linespace_trace_comp;
}

// An exact-mode pool: its values, at least one element (bindings need a non-empty buffer).
template <typename T>
std::unique_ptr<gpu::Buffer> exactPool(const gpu::Context& context, const std::vector<T>& values, const char* name) {
  auto buffer = std::make_unique<gpu::Buffer>(context, std::max<std::size_t>(values.size(), 1) * sizeof(T),
                                              vk::BufferUsageFlagBits::eStorageBuffer, name);
  std::memset(buffer->data(), 0, buffer->size());
  buffer->upload(std::span<const T>(values));
  return buffer;
}
constexpr vk::DeviceSize kCounterBytes = LS_COUNTER_WORDS * sizeof(std::uint32_t);

// Whether the moving meshes are traced with ray queries (LineSpaceSettings::movingTracer).
bool movingRayQueries(const gpu::Context& context, const LineSpaceSettings& settings, const DynamicBvh& dynamic) {
  using Moving = LineSpaceSettings::Moving;
  const bool rq = settings.movingTracer == Moving::Auto ? defaultTracer(context) == "rq"
                                                       : settings.movingTracer == Moving::RayQuery;
  return rq && !dynamic.empty();
}

constexpr std::uint32_t kDynamicRoot = 1;  // node 0 stays unused: inner index 0 marks an empty slot

// The dynamic BVH's buffers for `triangles` moving triangles: room for any rebuild
// (DynamicBvh::nodeCapacity) after the unused node 0; at least one triangle, as bindings need.
vk::DeviceSize bvhNodeBytes(std::uint64_t triangles) {
  return (kDynamicRoot + (triangles ? std::max<std::uint64_t>(1, triangles) : 0)) * sizeof(shared::BvhNode);
}
vk::DeviceSize bvhTriangleBytes(std::uint64_t triangles) {
  return std::max<std::uint64_t>(1, triangles) * sizeof(shared::BvhTriangle);
}

// The line space over `tree` (or a new N-tree over the static meshes when null), checked.
LineSpace buildChecked(const gpu::Context& context, const Scene& scene, const LineSpaceSettings& settings,
                       const NTree* tree = nullptr) {
  context.requireSubgroupArithmetic("LineSpaceTracer");
  const std::uint64_t moving = triangleCount(scene, MeshSet::Dynamic);
  const std::uint64_t limit = context.storageBufferRange();
  if (const std::uint64_t largest = std::max(bvhNodeBytes(moving), bvhTriangleBytes(moving)); largest > limit) {
    throw InputError("line space: the moving meshes of scene '" + scene.name + "' (" + std::to_string(moving) +
                     " triangles) need " + std::to_string(largest >> 20) + " MiB in one BVH buffer, but " +
                     context.deviceName() + " binds at most " + std::to_string(limit >> 20) +
                     " MiB per storage buffer (maxStorageBufferRange); animate fewer triangles");
  }
  const std::uint64_t dynamicBytes = bvhNodeBytes(moving) + bvhTriangleBytes(moving);
  if (!tree) return buildLineSpace(scene, settings, limit, MeshSet::Static, dynamicBytes);
  std::vector<shared::BvhTriangle> triangles;
  if (settings.shadows == LineSpaceSettings::Shadows::Exact) triangles = lineSpaceTriangles(scene, MeshSet::Static);
  return buildLineSpace(*tree, settings, limit, scene.name, dynamicBytes, std::move(triangles));
}

}  // namespace

LineSpaceTracer::LineSpaceTracer(const gpu::Context& context, const Scene& scene, const LineSpaceSettings& settings)
    : LineSpaceTracer(context, scene, buildChecked(context, scene, settings), settings) {}

LineSpaceTracer::LineSpaceTracer(const gpu::Context& context, const Scene& scene, const NTree& tree,
                                 const LineSpaceSettings& settings)
    : LineSpaceTracer(context, scene, buildChecked(context, scene, settings, &tree), settings) {}

LineSpaceTracer::LineSpaceTracer(const gpu::Context& context, const Scene& scene, LineSpace ls,
                                 const LineSpaceSettings& settings)
    : stats_(ls.stats),
      exact_(settings.shadows == LineSpaceSettings::Shadows::Exact),
      dynamic_(scene),
      push_{ls.n,
            ls.depth,
            shared::lsWordsPerNode(ls.n),
            exact_ ? 0.0f : settings.startOffsetCells * ls.nodes.front().size / std::pow(float(ls.n), float(ls.depth)),
            dynamic_.empty() ? BVH_NO_TREE : kDynamicRoot},
      cutouts_(context, scene),
      tree_(context, ls.tree.size() * sizeof(std::uint32_t), vk::BufferUsageFlagBits::eStorageBuffer, "ls tree pool"),
      nodes_(context, ls.nodes.size() * sizeof(shared::LsNode), vk::BufferUsageFlagBits::eStorageBuffer, "ls node pool"),
      bits_(context, ls.bits.size() * sizeof(std::uint32_t), vk::BufferUsageFlagBits::eStorageBuffer,
            "ls line-space pool"),
      counters_(context, kCounterBytes, vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eTransferDst,
                "ls counters"),
      bvhNodes_(context, bvhNodeBytes(dynamic_.triangleCount()), vk::BufferUsageFlagBits::eStorageBuffer,
                "ls dynamic bvh nodes"),
      bvhTriangles_(context, bvhTriangleBytes(dynamic_.triangleCount()), vk::BufferUsageFlagBits::eStorageBuffer,
                    "ls dynamic bvh triangles"),
      moving_(movingRayQueries(context, settings, dynamic_)
                  ? std::make_unique<SceneAccelerationStructures>(context, scene, BvhBuildSettings{}, MeshSet::Dynamic)
                  : nullptr),
      pipeline_(context, kernel(moving_ != nullptr, exact_), bindings(moving_ != nullptr, exact_),
                sizeof(shared::LsPush), exact_ ? "linespace exact trace pipeline" : "linespace trace pipeline") {
  tree_.upload(std::span<const std::uint32_t>(ls.tree));
  nodes_.upload(std::span<const shared::LsNode>(ls.nodes));
  bits_.upload(std::span<const std::uint32_t>(ls.bits));
  if (exact_) {
    leaves_ = exactPool(context, ls.leaves, "ls leaf records");
    leafTriangles_ = exactPool(context, ls.leafTriangles, "ls leaf triangle lists");
    triangles_ = exactPool(context, ls.triangles, "ls triangles");
  }
  push_.cutouts = cutouts_.trianglesAddress();
  push_.cutoutTexels = cutouts_.texelsAddress();
  std::memset(counters_.data(), 0, kCounterBytes);
  std::memset(bvhNodes_.data(), 0, bvhNodes_.size());  // defined contents even where no ray looks
  std::memset(bvhTriangles_.data(), 0, bvhTriangles_.size());
  dynamic_.attach(bvhNodes_, bvhTriangles_, kDynamicRoot, 0);
}

BvhRefitReport LineSpaceTracer::update(const Scene& scene) {
  return moving_ ? moving_->update(scene) : dynamic_.update(scene);
}

// The pools (with exact mode's) at LS_BINDING_*.
void LineSpaceTracer::addPools(gpu::Descriptors& descriptors) const {
  descriptors.buffer(LS_BINDING_TREE, tree_).buffer(LS_BINDING_NODES, nodes_).buffer(LS_BINDING_BITS, bits_);
  if (exact_) {
    descriptors.buffer(LS_BINDING_LEAVES, *leaves_)
        .buffer(LS_BINDING_LEAF_TRIANGLES, *leafTriangles_)
        .buffer(LS_BINDING_TRIANGLES, *triangles_);
  }
}

gpu::Descriptors& LineSpaceTracer::addBindings(gpu::Descriptors& descriptors) const {
  if (moving_) throw std::logic_error("LineSpaceTracer::addBindings: the moving meshes are traced with ray queries");
  addPools(descriptors);
  return descriptors.buffer(LS_BINDING_BVH_NODES, bvhNodes_).buffer(LS_BINDING_BVH_TRIANGLES, bvhTriangles_);
}

void LineSpaceTracer::record(const vk::raii::CommandBuffer& cmd, const TraceJob& job) {
  recordTraceStart(cmd, counters_);
  gpu::Descriptors descriptors;
  descriptors.buffer(LS_BINDING_COUNTERS, counters_);
  job.addTo(descriptors, LS_BINDING_TRACE_JOB);
  if (moving_) {
    SceneAccelerationStructures::recordBuildToTrace(cmd);
    addPools(descriptors);
    descriptors.accelerationStructure(LS_BINDING_BVH_NODES, moving_->top())
        .buffer(LS_BINDING_BVH_TRIANGLES, moving_->triangleIds());
  } else {
    addBindings(descriptors);
  }
  pipeline_.bind(cmd, descriptors);
  pipeline_.pushConstants(cmd, push_);
  cmd.dispatchIndirect(job.count.handle(), offsetof(shared::TraceCount, groupsX));
  gpu::computeToComputeAndHost(cmd);  // visibility for shading, counters for finish()
}

TraceReport LineSpaceTracer::finish(const TraceJob&) {
  const auto start = std::chrono::steady_clock::now();
  const auto words = counters_.download<std::uint32_t>(LS_COUNTER_WORDS);
  auto value = [&](std::uint32_t low) { return std::uint64_t(words[low]) | (std::uint64_t(words[low + 1]) << 32); };
  TraceReport report;
  report.rays = value(LS_COUNTER_RAYS);
  report.nodeVisits = value(LS_COUNTER_NODE_VISITS);
  report.triangleTests = value(LS_COUNTER_TRIANGLE_TESTS);
  report.hostMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace penumbra
