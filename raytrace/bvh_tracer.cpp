#include "raytrace/bvh_tracer.h"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <string>

#include "bvh_rays_comp.h"
#include "bvh_trace_comp.h"
#include "shared/trace.h"

namespace penumbra {
namespace {


// The trees are read through device addresses (BvhAddresses), so only the counters and the
// kernels' own buffers are bound.
constexpr gpu::Binding kTraceBindings[] = {{BVH_BINDING_COUNTERS, vk::DescriptorType::eStorageBuffer},
                                           {BVH_BINDING_TRACE_JOB, vk::DescriptorType::eStorageBuffer},
                                           {BVH_BINDING_TRACE_JOB + 1, vk::DescriptorType::eStorageBuffer},
                                           {BVH_BINDING_TRACE_JOB + 2, vk::DescriptorType::eStorageBuffer},
                                           {TRACE_BINDING_POSITION, vk::DescriptorType::eStorageImage},
                                           {TRACE_BINDING_NORMAL, vk::DescriptorType::eStorageImage}};
constexpr gpu::Binding kRaysBindings[] = {{BVH_BINDING_COUNTERS, vk::DescriptorType::eStorageBuffer},
                                          {BVH_BINDING_QUERIES, vk::DescriptorType::eStorageBuffer},
                                          {BVH_BINDING_HITS, vk::DescriptorType::eStorageBuffer}};

constexpr vk::DeviceSize kCounterBytes = BVH_COUNTER_WORDS * sizeof(std::uint32_t);

std::string mebibytes(std::uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB"; }

// Checks what can be known before building (the device, and the triangle buffer, the larger of
// the two buffers), builds the static tree, then checks the node buffer (both trees).
Bvh buildChecked(const gpu::Context& context, const Scene& scene, const BvhBuildSettings& settings) {
  context.requireSubgroupArithmetic("BvhTracer");
  const std::uint64_t limit = context.maxBufferBytes();
  const std::uint64_t triangles = scene.triangleCount();
  const std::uint64_t dynamicTriangles = triangleCount(scene, MeshSet::Dynamic);
  auto tooLarge = [&](const char* what, std::uint64_t bytes) {
    return InputError("BVH: scene '" + scene.name + "' (" + std::to_string(triangles) + " triangles) needs " +
                      mebibytes(bytes) + " of " + what + ", but " + context.deviceName() + " holds at most " +
                      mebibytes(limit) + " in one buffer (maxMemoryAllocationSize, maxBufferSize); use a smaller scene or level");
  };
  if (BvhBuilder::triangleBytes(triangles) > limit)
    throw tooLarge("BVH triangles", BvhBuilder::triangleBytes(triangles));
  Bvh bvh = BvhBuilder(settings).build(scene, MeshSet::Static);
  const std::uint64_t nodeBytes =
      (bvh.nodes.size() + (dynamicTriangles ? std::max<std::uint64_t>(1, dynamicTriangles) : 0)) *
      sizeof(shared::BvhNode);
  if (nodeBytes > limit) throw tooLarge("BVH nodes", nodeBytes);
  if (bvh.triangles.size() + dynamicTriangles >= BVH_NO_HIT) throw tooLarge("BVH triangles", BVH_NO_HIT);
  return bvh;
}

}  // namespace

BvhTracer::BvhTracer(const gpu::Context& context, const Scene& scene, const BvhBuildSettings& settings)
    : BvhTracer(context, scene, buildChecked(context, scene, settings), settings) {}

BvhTracer::BvhTracer(const gpu::Context& context, const Scene& scene, Bvh bvh, const BvhBuildSettings& settings)
    : context_(context),
      stats_(bvh.stats),
      dynamic_(scene, settings),
      dynamicRoot_(dynamic_.empty() ? BVH_NO_TREE : std::uint32_t(bvh.nodes.size())),
      staticTriangles_(std::uint32_t(bvh.triangles.size())),
      nodes_(context,
             (bvh.nodes.size() + (dynamic_.empty() ? 0 : dynamic_.nodeCapacity())) * sizeof(shared::BvhNode),
             vk::BufferUsageFlagBits::eShaderDeviceAddress, "bvh nodes"),
      triangles_(context, (bvh.triangles.size() + dynamic_.triangleCount()) * sizeof(shared::BvhTriangle),
                 vk::BufferUsageFlagBits::eShaderDeviceAddress, "bvh triangles"),
      cutouts_(context, scene),
      counters_(context, kCounterBytes, vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eTransferDst,
                "bvh counters"),
      raysCounters_(context, kCounterBytes, vk::BufferUsageFlagBits::eStorageBuffer, "bvh ray counters"),
      tracePipeline_(context, bvh_trace_comp, kTraceBindings, sizeof(shared::BvhTracePush), "bvh trace pipeline"),
      raysPipeline_(context, bvh_rays_comp, kRaysBindings, sizeof(shared::BvhRaysPush), "bvh rays pipeline"),
      rayBatches_(context, "bvh") {
  // The static tree is written once, here; update() only ever writes after it.
  std::memcpy(nodes_.data(), bvh.nodes.data(), bvh.nodes.size() * sizeof(shared::BvhNode));
  std::memcpy(triangles_.data(), bvh.triangles.data(), bvh.triangles.size() * sizeof(shared::BvhTriangle));
  std::memset(counters_.data(), 0, kCounterBytes);
  if (!dynamic_.empty()) {
    const BvhStats& d = dynamic_.bvh().stats;
    stats_.nodes += d.nodes;
    stats_.leaves += d.leaves;
    stats_.triangles += d.triangles;
    stats_.buildMs += d.buildMs;
    dynamic_.attach(nodes_, triangles_, dynamicRoot_, staticTriangles_);
  }
  stats_.bytes = nodes_.size() + triangles_.size() + cutouts_.bytes();
}

BvhRefitReport BvhTracer::update(const Scene& scene) { return dynamic_.update(scene); }

shared::BvhAddresses BvhTracer::addresses() const {
  return cutouts_.with({gpu::addressHalves(nodes_), gpu::addressHalves(triangles_), {}, {}});
}

void BvhTracer::record(const vk::raii::CommandBuffer& cmd, const TraceJob& job) {
  recordTraceStart(cmd, counters_);
  gpu::Descriptors descriptors;
  descriptors.buffer(BVH_BINDING_COUNTERS, counters_);
  tracePipeline_.bind(cmd, job.addTo(descriptors, BVH_BINDING_TRACE_JOB));
  tracePipeline_.pushConstants(cmd, shared::BvhTracePush{addresses(), dynamicRoot_, 0u, 0u, 0u});
  cmd.dispatchIndirect(job.count.handle(), offsetof(shared::TraceCount, groupsX));
  gpu::computeToComputeAndHost(cmd);  // visibility for shading, counters for finish()
}

TraceReport BvhTracer::finish(const TraceJob&) {
  const auto start = std::chrono::steady_clock::now();
  TraceReport report = readCounters(counters_);
  report.hostMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return report;
}

TraceReport BvhTracer::readCounters(const gpu::Buffer& counters) {
  const auto words = counters.download<std::uint32_t>(BVH_COUNTER_WORDS);
  auto value = [&](std::uint32_t low) { return std::uint64_t(words[low]) | (std::uint64_t(words[low + 1]) << 32); };
  TraceReport report;
  report.rays = value(BVH_COUNTER_RAYS);
  report.nodeVisits = value(BVH_COUNTER_NODE_VISITS);
  report.triangleTests = value(BVH_COUNTER_TRIANGLE_TESTS);
  return report;
}

std::vector<shared::RayHit> BvhTracer::traceRays(std::span<const shared::RayQuery> rays, bool anyHit) {
  std::memset(raysCounters_.data(), 0, kCounterBytes);  // no GPU work is in flight between submissions
  auto out = rayBatches_.trace(rays, BVH_GROUP_SIZE,
                               [&](const vk::raii::CommandBuffer& cmd, const gpu::Buffer& queries,
                                   const gpu::Buffer& hits, std::uint32_t first, std::uint32_t count) {
                                 raysPipeline_.bind(cmd, gpu::Descriptors{}
                                                             .buffer(BVH_BINDING_COUNTERS, raysCounters_)
                                                             .buffer(BVH_BINDING_QUERIES, queries)
                                                             .buffer(BVH_BINDING_HITS, hits));
                                 raysPipeline_.pushConstants(cmd, shared::BvhRaysPush{addresses(), first, count,
                                                                                      anyHit ? 1u : 0u, dynamicRoot_});
                                 cmd.dispatch((count + BVH_GROUP_SIZE - 1) / BVH_GROUP_SIZE, 1, 1);
                               });
  raysReport_ = readCounters(raysCounters_);
  return out;
}

}  // namespace penumbra
