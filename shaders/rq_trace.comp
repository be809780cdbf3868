#version 460
// Shadow rays of the ray-query tracer: bvh_trace.comp with the occlusion test answered by the
// driver's acceleration structures (rayQueryEXT, first hit ends the ray). Same samples, origins
// and ray ends (shadow_rays.glsl); writes visibility[point.pixel] itself.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_query : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#include "shared/trace.h"
#include "shadow_rays.glsl"
#include "rq_common.glsl"
layout(local_size_x = TRACE_GROUP_SIZE) in;
layout(std430, binding = BVH_BINDING_TRACE_JOB) readonly buffer Count { TraceCount traceCount; };
layout(std430, binding = BVH_BINDING_TRACE_JOB + 1) readonly buffer Frame { FrameData frame; };
layout(std430, binding = BVH_BINDING_TRACE_JOB + 2) writeonly buffer Visibility { float visibility[]; };
#include "trace_points.glsl"

bool shadowOccluded(ShadingPoint point, vec3 origin, vec3 dir, float tMax, out float blockerT) {
  RayHit hit = rqTrace(origin, dir, 0.0f, tMax, true);
  blockerT = hit.t;
  return hit.triangle != BVH_NO_HIT;
}

void main() {
  uint rays = 0u;
  traceShadows(rays);
  rqAddRays(rays);
}
