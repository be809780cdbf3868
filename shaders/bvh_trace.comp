#version 450
// Shadow rays of the BVH tracer: one invocation per ShadingPoint of the TraceJob, dispatched
// indirectly from TraceCount. Mirrors EmbreeTracer::traceShadows sample for sample
// (shadow_rays.glsl), and writes visibility[point.pixel] itself (write-back fused into the trace).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#include "shared/bvh.h"
#include "shared/trace.h"
#include "shadow_rays.glsl"
layout(push_constant) uniform Push { BvhTracePush push; };
#define BVH_ADDRESSES push.bvh
#include "bvh_traverse.glsl"
layout(local_size_x = TRACE_GROUP_SIZE) in;
layout(std430, binding = BVH_BINDING_TRACE_JOB) readonly buffer Count { TraceCount traceCount; };
layout(std430, binding = BVH_BINDING_TRACE_JOB + 1) readonly buffer Frame { FrameData frame; };
layout(std430, binding = BVH_BINDING_TRACE_JOB + 2) writeonly buffer Visibility { float visibility[]; };
#include "trace_points.glsl"

bool shadowOccluded(ShadingPoint point, vec3 origin, vec3 dir, float tMax, out float blockerT) {
  RayHit hit = bvhAnyHitRecord(origin, dir, 0.0f, tMax, push.dynamicRoot);
  blockerT = hit.t;
  return hit.triangle != BVH_NO_HIT;
}

void main() {
  uint rays = 0u;
  traceShadows(rays);
  bvhAddCounters(rays);
}
