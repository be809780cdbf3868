// BVH closest hit with candidate line spaces (Keul et al. 2018, 3.2 "Adaptation to BVH"): an inner
// node that has a line space (csNodeMap[node] != CS_NONE, the nodes at depth D) is answered by
// csHit instead of being descended, like a leaf; leaves and the nodes above depth D stay exact.
// The traversal is bvh_traverse.glsl's (BVH_LINE_SPACES), so this file must come before any other
// include of it. The includer provides what bvh_traverse.glsl needs (BVH_ADDRESSES or the
// BVH_BINDING_* buffers, the counter buffer or BVH_NO_COUNTERS, the subgroup extensions) and what
// candidate_lookup.glsl needs (CS_PARAMS, the CS_BINDING_* buffers), and binds the per-node map at
// CS_BINDING_NODE_MAP. Statistics of the calling invocation: bvhNodeVisits, bvhTriangleTests
// (exact triangles) and csCandidateTests (candidate planes). Not compiled on its own.
#ifndef PENUMBRA_BVH_LS_TRAVERSE_GLSL
#define PENUMBRA_BVH_LS_TRAVERSE_GLSL
#ifdef PENUMBRA_BVH_TRAVERSE_GLSL
#error "include bvh_ls_traverse.glsl before bvh_traverse.glsl"
#endif
#include "candidate_lookup.glsl"

layout(std430, binding = CS_BINDING_NODE_MAP) readonly buffer CsNodeMap { uint csNodeMap[]; };

// Line space of the child in a slot, or CS_NONE (a leaf, an empty slot, or an exact inner node).
uint bvhLsChildSpace(BvhChild child) {
  if (child.count > 0u || child.index == 0u) return CS_NONE;
  return csNodeMap[child.index];
}

// Asks line space `ls` within [tMin, tMax]; a hit shortens tMax and replaces `hit` (pad1 =
// CS_HIT_FROM_LINE_SPACE). Returns whether it found one.
bool bvhLsAsk(uint ls, vec3 origin, vec3 dir, float tMin, inout float tMax, inout RayHit hit) {
  float t;
  uint triangle;
  vec3 normal;
  if (!csHit(ls, origin, dir, tMin, tMax, t, triangle, normal)) return false;
  tMax = t;
  hit = RayHit(t, triangle, 0u, CS_HIT_FROM_LINE_SPACE);
  return true;
}

#define BVH_LINE_SPACES
#include "bvh_traverse.glsl"

// The nearest hit within [tMin, tMax] in the static tree (root 0): t < 0 and BVH_NO_HIT on a miss;
// hit.pad1 = CS_HIT_FROM_LINE_SPACE when a line space answered. useLineSpace false: the exact BVH
// closest hit (every node descended).
RayHit bvhLsClosestHit(vec3 origin, vec3 dir, float tMin, float tMax, bool useLineSpace) {
  return bvhTraverse(0u, origin, dir, tMin, tMax, false, useLineSpace);
}
#endif  // PENUMBRA_BVH_LS_TRAVERSE_GLSL
