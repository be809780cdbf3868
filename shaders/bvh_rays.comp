#version 450
// Arbitrary rays against the BVH (BvhTracer::traceRays): RayQuery in, RayHit out, any-hit or
// closest-hit by push constant. Counts traversal steps like the shadow kernel.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#include "shared/bvh.h"
layout(push_constant) uniform Push { BvhRaysPush push; };
#define BVH_ADDRESSES push.bvh
#include "bvh_traverse.glsl"
layout(local_size_x = BVH_GROUP_SIZE) in;
layout(std430, binding = BVH_BINDING_QUERIES) readonly buffer Queries { RayQuery queries[]; };
layout(std430, binding = BVH_BINDING_HITS) writeonly buffer Hits { RayHit hits[]; };

void main() {
  uint rays = 0u;
  if (gl_GlobalInvocationID.x < push.count) {
    uint index = push.first + gl_GlobalInvocationID.x;
    RayQuery q = queries[index];
    hits[index] = push.anyHit != 0u ? bvhAnyHitRecord(q.origin, q.direction, q.tMin, q.tMax, push.dynamicRoot)
                                    : bvhClosestHit(q.origin, q.direction, q.tMin, q.tMax, push.dynamicRoot);
    rays = 1u;
  }
  bvhAddCounters(rays);
}
