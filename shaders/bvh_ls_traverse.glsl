// BVH closest hit with candidate line spaces (Keul et al. 2018, 3.2 "Adaptation to BVH"): an inner
// node that has a line space (csNodeMap[node] != CS_NONE, the nodes at depth D) is answered by
// csHit instead of being descended, like a leaf; leaves and the nodes above depth D stay exact
// (bvh_traverse.glsl's triangle test). Included by candidate_rays.comp; usable from any kernel
// (not compiled on its own). The includer provides what bvh_traverse.glsl needs (BVH_ADDRESSES or
// the BVH_BINDING_* buffers, the counter buffer or BVH_NO_COUNTERS, the subgroup extensions) and
// what candidate_lookup.glsl needs (CS_PARAMS, the CS_BINDING_* buffers), and binds the per-node
// map at CS_BINDING_NODE_MAP. Statistics of the calling invocation: bvhNodeVisits,
// bvhTriangleTests (exact triangles) and csCandidateTests (candidate planes). It includes
// bvh_traverse.glsl and candidate_lookup.glsl itself (both guarded, so including them again is harmless).
#ifndef PENUMBRA_BVH_LS_TRAVERSE_GLSL
#define PENUMBRA_BVH_LS_TRAVERSE_GLSL
#include "bvh_traverse.glsl"
#include "candidate_lookup.glsl"

layout(std430, binding = CS_BINDING_NODE_MAP) readonly buffer CsNodeMap { uint csNodeMap[]; };

// Line space of the child in a slot, or CS_NONE (a leaf, an empty slot, or an exact inner node).
uint bvhLsChildSpace(BvhChild child, bool useLineSpace) {
  if (!useLineSpace || child.count > 0u || child.index == 0u) return CS_NONE;
  return csNodeMap[child.index];
}

// Asks line space `ls` within [tMin, tMax]; a hit shortens tMax and replaces `hit` (pad1 =
// CS_HIT_FROM_LINE_SPACE) and `normal`.
void bvhLsAsk(uint ls, vec3 origin, vec3 dir, float tMin, inout float tMax, inout RayHit hit, inout vec3 normal) {
  float t;
  uint triangle;
  vec3 n;
  if (!csHit(ls, origin, dir, tMin, tMax, t, triangle, n)) return;
  tMax = t;
  hit = RayHit(t, triangle, 0u, CS_HIT_FROM_LINE_SPACE);
  normal = n;
}

// The nearest hit within [tMin, tMax] in the static tree (root 0): t < 0 and BVH_NO_HIT on a miss;
// hit.pad1 = CS_HIT_FROM_LINE_SPACE when a line space answered. `normal`: the shading normal at the
// hit (vertex normals interpolated, or extrapolated on a candidate's plane), on the vertex normals'
// side. useLineSpace false: the exact BVH closest hit (every node descended).
RayHit bvhLsClosestHit(vec3 origin, vec3 dir, float tMin, float tMax, bool useLineSpace, out vec3 normal) {
  RayHit hit = RayHit(-1.0f, BVH_NO_HIT, 0u, 0u);
  normal = vec3(0.0f, 0.0f, 1.0f);
  vec3 lsNormal = normal;
  if (useLineSpace && csNodeMap[0] != CS_NONE) {  // D = 0: the root's line space answers alone
    ++bvhNodeVisits;
    bvhLsAsk(csNodeMap[0], origin, dir, tMin, tMax, hit, normal);
    return hit;
  }
  vec3 invDir = bvhInverseDirection(dir);
  uint stack[BVH_STACK_SIZE];
  uint depth = 0u;
  uint node = 0u;
  for (;;) {
    ++bvhNodeVisits;
    BvhNode n = bvhNodes[node];
    float enter0, enter1;
    bool go0 = bvhSlab(n.child[0].lo, n.child[0].hi, origin, invDir, tMin, tMax, enter0);
    bool go1 = bvhSlab(n.child[1].lo, n.child[1].hi, origin, invDir, tMin, tMax, enter1);
    // Leaves and line-space nodes are answered at once; only exact inner children go on.
    if (go0 && n.child[0].count > 0u) {
      bvhLeaf(n.child[0].index, n.child[0].count, origin, dir, tMin, tMax, hit, false);
      go0 = false;
    }
    if (go1 && n.child[1].count > 0u) {
      bvhLeaf(n.child[1].index, n.child[1].count, origin, dir, tMin, tMax, hit, false);
      go1 = false;
    }
    go1 = go1 && n.child[1].index != 0u;  // inner index 0 (the root) marks an empty slot
    uint ls0 = go0 ? bvhLsChildSpace(n.child[0], useLineSpace) : CS_NONE;
    uint ls1 = go1 ? bvhLsChildSpace(n.child[1], useLineSpace) : CS_NONE;
    // Nearer line space first, so the farther one's range is already cut by a hit.
    bool firstNearer = enter0 <= enter1;
    uint lsA = firstNearer ? ls0 : ls1, lsB = firstNearer ? ls1 : ls0;
    if (lsA != CS_NONE) bvhLsAsk(lsA, origin, dir, tMin, tMax, hit, lsNormal);
    if (lsB != CS_NONE) bvhLsAsk(lsB, origin, dir, tMin, tMax, hit, lsNormal);
    go0 = go0 && ls0 == CS_NONE;
    go1 = go1 && ls1 == CS_NONE;
    // A hit may have shortened the ray to before an inner child's entry.
    float limit = tMax * kBvhExitScale;
    go0 = go0 && enter0 <= limit;
    go1 = go1 && enter1 <= limit;
    if (go0 && go1) {
      stack[depth++] = firstNearer ? n.child[1].index : n.child[0].index;
      node = firstNearer ? n.child[0].index : n.child[1].index;
    } else if (go0 || go1) {
      node = go0 ? n.child[0].index : n.child[1].index;
    } else {
      if (depth == 0u) break;
      node = stack[--depth];
    }
  }
  if (hit.triangle != BVH_NO_HIT) {
    if (hit.pad1 == CS_HIT_FROM_LINE_SPACE) {
      normal = lsNormal;
    } else {
      vec3 face;
      if (!csTriangleNormals(csSceneTriangles[hit.triangle], origin + hit.t * dir, normal, face)) normal = face;
    }
  }
  return hit;
}
#endif  // PENUMBRA_BVH_LS_TRAVERSE_GLSL
