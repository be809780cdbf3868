#version 460
// Arbitrary rays against the driver's acceleration structures (RayQueryTracer::traceRays):
// RayQuery in, RayHit out, any-hit or closest-hit by push constant, as bvh_rays.comp.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_query : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#include "rq_common.glsl"
layout(local_size_x = BVH_GROUP_SIZE) in;
layout(std430, binding = BVH_BINDING_QUERIES) readonly buffer Queries { RayQuery queries[]; };
layout(std430, binding = BVH_BINDING_HITS) writeonly buffer Hits { RayHit hits[]; };
layout(push_constant) uniform Push { BvhRaysPush push; };

void main() {
  uint rays = 0u;
  if (gl_GlobalInvocationID.x < push.count) {
    uint index = push.first + gl_GlobalInvocationID.x;
    RayQuery q = queries[index];
    hits[index] = rqTrace(q.origin, q.direction, q.tMin, q.tMax, push.anyHit != 0u);
    rays = 1u;
  }
  rqAddRays(rays);
}
