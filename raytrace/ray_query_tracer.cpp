#include "raytrace/ray_query_tracer.h"

#include <chrono>
#include <cstddef>
#include <cstring>

#include "raytrace/bvh_tracer.h"
#include "rq_rays_comp.h"
#include "rq_trace_comp.h"
#include "shared/ray_query.h"
#include "shared/trace.h"

namespace penumbra {
namespace {

using Type = vk::DescriptorType;

constexpr gpu::Binding kTraceBindings[] = {
    {RQ_BINDING_SCENE, Type::eAccelerationStructureKHR}, {RQ_BINDING_TRIANGLE_IDS, Type::eStorageBuffer},
    {RQ_BINDING_COUNTERS, Type::eStorageBuffer},         {BVH_BINDING_TRACE_JOB, Type::eStorageBuffer},
    {BVH_BINDING_TRACE_JOB + 1, Type::eStorageBuffer},   {BVH_BINDING_TRACE_JOB + 2, Type::eStorageBuffer},
    {TRACE_BINDING_POSITION, Type::eStorageImage},       {TRACE_BINDING_NORMAL, Type::eStorageImage}};
constexpr gpu::Binding kRaysBindings[] = {{RQ_BINDING_SCENE, Type::eAccelerationStructureKHR},
                                          {RQ_BINDING_TRIANGLE_IDS, Type::eStorageBuffer},
                                          {RQ_BINDING_COUNTERS, Type::eStorageBuffer},
                                          {BVH_BINDING_QUERIES, Type::eStorageBuffer},
                                          {BVH_BINDING_HITS, Type::eStorageBuffer}};
constexpr vk::DeviceSize kCounterBytes = BVH_COUNTER_WORDS * sizeof(std::uint32_t);

const gpu::Context& checked(const gpu::Context& context) {
  context.requireRayQuery("--tracer rq");
  context.requireSubgroupArithmetic("RayQueryTracer");
  return context;
}

}  // namespace

RayQueryTracer::RayQueryTracer(const gpu::Context& context, const Scene& scene, const BvhBuildSettings& settings)
    : structures_(checked(context), scene, settings),
      counters_(context, kCounterBytes, vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eTransferDst,
                "rq counters"),
      raysCounters_(context, kCounterBytes, vk::BufferUsageFlagBits::eStorageBuffer, "rq ray counters"),
      tracePipeline_(context, rq_trace_comp, kTraceBindings, 0, "rq trace pipeline"),
      raysPipeline_(context, rq_rays_comp, kRaysBindings, sizeof(shared::BvhRaysPush), "rq rays pipeline"),
      rayBatches_(context, "rq") {
  std::memset(counters_.data(), 0, kCounterBytes);
}

void RayQueryTracer::record(const vk::raii::CommandBuffer& cmd, const TraceJob& job) {
  recordTraceStart(cmd, counters_);
  SceneAccelerationStructures::recordBuildToTrace(cmd);
  gpu::Descriptors descriptors;
  descriptors.accelerationStructure(RQ_BINDING_SCENE, structures_.top())
      .buffer(RQ_BINDING_TRIANGLE_IDS, structures_.triangleIds())
      .buffer(RQ_BINDING_COUNTERS, counters_);
  tracePipeline_.bind(cmd, job.addTo(descriptors, BVH_BINDING_TRACE_JOB));
  cmd.dispatchIndirect(job.count.handle(), offsetof(shared::TraceCount, groupsX));
  gpu::computeToComputeAndHost(cmd);  // visibility for shading, counters for finish()
}

TraceReport RayQueryTracer::finish(const TraceJob&) {
  const auto start = std::chrono::steady_clock::now();
  TraceReport report;
  report.rays = BvhTracer::readCounters(counters_).rays;  // the driver's traversal is not counted
  report.hostMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return report;
}

std::vector<shared::RayHit> RayQueryTracer::traceRays(std::span<const shared::RayQuery> rays, bool anyHit) {
  std::memset(raysCounters_.data(), 0, kCounterBytes);
  return rayBatches_.trace(rays, BVH_GROUP_SIZE, [&](const vk::raii::CommandBuffer& cmd, const gpu::Buffer& queries,
                                                     const gpu::Buffer& hits, std::uint32_t first, std::uint32_t count) {
    SceneAccelerationStructures::recordBuildToTrace(cmd);
    raysPipeline_.bind(cmd, gpu::Descriptors{}
                                .accelerationStructure(RQ_BINDING_SCENE, structures_.top())
                                .buffer(RQ_BINDING_TRIANGLE_IDS, structures_.triangleIds())
                                .buffer(RQ_BINDING_COUNTERS, raysCounters_)
                                .buffer(BVH_BINDING_QUERIES, queries)
                                .buffer(BVH_BINDING_HITS, hits));
    // The kernel reads the driver's acceleration structures: no BVH addresses.
    raysPipeline_.pushConstants(cmd, shared::BvhRaysPush{{}, first, count, anyHit ? 1u : 0u, 0u});
    cmd.dispatch((count + BVH_GROUP_SIZE - 1) / BVH_GROUP_SIZE, 1, 1);
  });
}

}  // namespace penumbra
