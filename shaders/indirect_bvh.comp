#version 450
// Indirect rays (indirect_trace.glsl) on the GPU BVH: exact closest and any hits, both trees.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#include "shared/indirect.h"
#include "shared/bvh.h"
layout(push_constant) uniform Push {
  IndirectParams params;
  BvhTracePush bvhPush;
};
#define BVH_ADDRESSES bvhPush.bvh
#define BVH_NO_COUNTERS
#include "bvh_traverse.glsl"

bool indirectClosest(vec3 origin, vec3 dir, float tMin, float tMax, out float t, out uint triangle) {
  RayHit hit = bvhClosestHit(origin, dir, tMin, tMax, bvhPush.dynamicRoot);
  t = hit.t;
  triangle = hit.triangle;
  return hit.triangle != BVH_NO_HIT;
}
bool indirectOccluded(vec3 origin, vec3 dir, float tMin, float tMax, bool aoRay) {
  return bvhAnyHitRecord(origin, dir, tMin, tMax, bvhPush.dynamicRoot).triangle != BVH_NO_HIT;
}
uint indirectVisits() { return bvhNodeVisits; }
uint indirectTests() { return bvhTriangleTests; }

#include "indirect_trace.glsl"
