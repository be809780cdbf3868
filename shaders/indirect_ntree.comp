#version 450
// Indirect rays (indirect_trace.glsl) on the N-tree's line space in exact mode (Keul et al. 2017's
// tree; linespace_traverse.glsl with LS_EXACT): the set shaft bits lead to the leaf cells, whose
// triangles are tested as the BVH tests them, front to back (lsClosestHit). The moving meshes are
// not in the line space: their own BVH (as linespace_trace.glsl traces them) is asked for a nearer
// hit, so every answer is exact, the closest of both.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
// The moving meshes' BVH at the line space's bindings, set before anything includes shared/bvh.h.
#define BVH_BINDING_NODES LS_BINDING_BVH_NODES
#define BVH_BINDING_TRIANGLES LS_BINDING_BVH_TRIANGLES
#include "shared/linespace.h"
#include "shared/indirect.h"
layout(push_constant) uniform Push {
  IndirectParams params;
  LsPush lsPush;
};
#define LS_PUSH_DECLARED
#define LS_NO_COUNTERS
#define LS_EXACT
#include "linespace_traverse.glsl"
#define BVH_NO_COUNTERS
#define BVH_CUTOUTS lsPush.cutouts, lsPush.cutoutTexels
#include "bvh_traverse.glsl"

bool indirectClosest(vec3 origin, vec3 dir, float tMin, float tMax, out float t, out uint triangle) {
  bool found = lsClosestHit(origin, dir, tMin, tMax, t, triangle);
  if (lsPush.dynamicRoot != BVH_NO_TREE) {
    RayHit moving = bvhTraverse(lsPush.dynamicRoot, origin, dir, tMin, found ? t : tMax, false);
    if (moving.triangle != BVH_NO_HIT) {
      t = moving.t;
      triangle = moving.triangle;
      found = true;
    }
  }
  return found;
}
bool indirectOccluded(vec3 origin, vec3 dir, float tMin, float tMax, bool aoRay) {
  if (lsOccluded(origin, dir, tMin, tMax)) return true;
  return lsPush.dynamicRoot != BVH_NO_TREE &&
         bvhTraverse(lsPush.dynamicRoot, origin, dir, tMin, tMax, true).triangle != BVH_NO_HIT;
}
uint indirectVisits() { return lsNodeVisits + bvhNodeVisits; }
uint indirectTests() { return lsTriangleTests + bvhTriangleTests; }

#include "indirect_trace.glsl"
