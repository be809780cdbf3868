#version 460
// Indirect rays (indirect_trace.glsl) with inline ray queries on the driver's acceleration
// structures (the path that uses ray-tracing hardware where a GPU has it): exact closest and any
// hits; the driver's traversal reports no node visits.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_query : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#include "shared/bvh.h"
#include "shared/indirect.h"
layout(push_constant) uniform Push { IndirectParams params; };
#define RQ_NO_COUNTERS
#include "rq_common.glsl"

bool indirectClosest(vec3 origin, vec3 dir, float tMin, float tMax, out float t, out uint triangle) {
  RayHit hit = rqTrace(origin, dir, tMin, tMax, false);
  t = hit.t;
  triangle = hit.triangle;
  return hit.triangle != BVH_NO_HIT;
}
bool indirectOccluded(vec3 origin, vec3 dir, float tMin, float tMax, bool aoRay) {
  return rqTrace(origin, dir, tMin, tMax, true).triangle != BVH_NO_HIT;
}
uint indirectVisits() { return 0u; }
uint indirectTests() { return 0u; }

#include "indirect_trace.glsl"
