#version 450
// Indirect rays (indirect_trace.glsl) on the BVH with candidate line spaces (Keul et al. 2018):
// ao and bounce rays take their closest hit from the line spaces at depth D (approximate); the
// shadow rays from the bounces' hits stay exact (any hit on the same BVH).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#include "shared/indirect.h"
#include "shared/candidates.h"
layout(push_constant) uniform Push {
  IndirectParams params;
  BvhTracePush bvhPush;
  CsParams cs;
};
#define BVH_ADDRESSES bvhPush.bvh
#define BVH_NO_COUNTERS
#define CS_PARAMS cs
#include "bvh_ls_traverse.glsl"

bool indirectClosest(vec3 origin, vec3 dir, float tMin, float tMax, out float t, out uint triangle) {
  RayHit hit = bvhLsClosestHit(origin, dir, tMin, tMax, true);
  t = hit.t;
  triangle = hit.triangle;
  return hit.triangle != BVH_NO_HIT;
}
// ao rays ask the line spaces too (any hit within the radius); shadow rays are exact.
bool indirectOccluded(vec3 origin, vec3 dir, float tMin, float tMax, bool aoRay) {
  return bvhTraverse(0u, origin, dir, tMin, tMax, true, aoRay).triangle != BVH_NO_HIT;
}
uint indirectVisits() { return bvhNodeVisits; }
uint indirectTests() { return bvhTriangleTests + csCandidateTests; }

#include "indirect_trace.glsl"
