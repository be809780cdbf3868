#version 450
// Indirect rays (indirect_trace.glsl) on the N-tree with candidate line spaces, the paper's
// NTree + LS(D) (Keul et al. 2018, 3.2 "Adaptation to NTree"): ao and bounce rays take their
// closest hit from the candidate line spaces of the N-tree's nodes at level D and of shallower
// nodes with fewer than T triangles (approximate; linespace_traverse.glsl with LS_CANDIDATES), the
// binary line space's bits skipping empty shafts above them. The shadow rays from the bounces'
// hits use the N-tree's binary line space (lsOccluded: a set shaft bit at the second-to-last level
// means occluded, the start node skipped), as the paper traces shadow rays; both exact on the
// moving meshes' own BVH (closest of both, any hit of either).
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
// The candidate buffers beside the line space's LS_BINDING_* (shared/candidates.h).
#define CS_BINDING_BOXES CS_NTREE_BINDING_BOXES
#define CS_BINDING_BITS CS_NTREE_BINDING_BITS
#define CS_BINDING_OFFSETS CS_NTREE_BINDING_OFFSETS
#define LS_CANDIDATE_NODE_MAP_BINDING CS_NTREE_BINDING_NODE_MAP
#include "shared/candidates.h"
layout(push_constant) uniform Push {
  IndirectParams params;
  LsPush lsPush;
  CsParams cs;
};
#define CS_PARAMS cs
#include "candidate_lookup.glsl"
#define LS_PUSH_DECLARED
#define LS_NO_COUNTERS
#define LS_CANDIDATES
#include "linespace_traverse.glsl"
#define BVH_NO_COUNTERS
#define BVH_CUTOUTS lsPush.cutouts, lsPush.cutoutTexels
#include "bvh_traverse.glsl"

bool indirectClosest(vec3 origin, vec3 dir, float tMin, float tMax, out float t, out uint triangle) {
  bool found = lsCandidateClosestHit(origin, dir, tMin, tMax, t, triangle);
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
// ao rays: the candidate line spaces' closest hit within the radius; shadow rays: the binary line
// space from lsPush.startOffset above the surface on (as linespace_trace.glsl offsets them).
bool indirectOccluded(vec3 origin, vec3 dir, float tMin, float tMax, bool aoRay) {
  if (aoRay) {
    float t;
    uint triangle;
    return indirectClosest(origin, dir, tMin, tMax, t, triangle);
  }
  if (lsOccluded(origin, dir, min(tMin + lsPush.startOffset, tMax), tMax)) return true;
  return lsPush.dynamicRoot != BVH_NO_TREE &&
         bvhTraverse(lsPush.dynamicRoot, origin, dir, tMin, tMax, true).triangle != BVH_NO_HIT;
}
uint indirectVisits() { return lsNodeVisits + bvhNodeVisits; }
uint indirectTests() { return lsTriangleTests + bvhTriangleTests + csCandidateTests; }

#include "indirect_trace.glsl"
