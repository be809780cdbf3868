// BVH traversal, included by bvh_trace.comp, bvh_rays.comp and linespace_trace.comp (not
// compiled on its own). Reads the nodes and triangles through the device addresses in
// BVH_ADDRESSES (a BvhAddresses the includer declared first, e.g. in its push constants; it then
// enables GL_EXT_buffer_reference and GL_EXT_buffer_reference_uvec2), else from storage buffers
// at BVH_BINDING_*; declares the counter buffer (BVH_NO_COUNTERS: no counter buffer and no
// bvhAddCounters, for kernels with their own); includers enable GL_KHR_shader_subgroup_basic and
// _arithmetic (for bvhAddCounters).
// The buffers may hold two trees (shared/bvh.h): the static one at node 0 and a dynamic one
// whose root the caller passes; bvhAnyHit and bvhClosestHit answer for both.
// Each visit fetches one 64-byte node and slab-tests both child boxes; leaves are tested at once,
// inner children are entered nearer first with the farther one on a short per-invocation stack.
// The triangle test is Embree's robust one (triangle_test.glsl, shared with the line space's exact
// mode), so rays that hit a shared edge or vertex find a triangle here exactly when they do in the
// reference.
#ifndef PENUMBRA_BVH_TRAVERSE_GLSL
#define PENUMBRA_BVH_TRAVERSE_GLSL
#include "shared/bvh.h"
#include "triangle_test.glsl"

#ifdef BVH_ADDRESSES
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer BvhNodeArray { BvhNode v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer BvhTriangleArray { BvhTriangle v[]; };
#define bvhNodes BvhNodeArray(BVH_ADDRESSES.nodes).v
#define bvhTriangles BvhTriangleArray(BVH_ADDRESSES.triangles).v
#include "cutout_test.glsl"

// Whether a candidate hit at barycentrics `bary` on cut-out triangle `cutout` (BvhTriangle.cutout)
// falls where its texture cuts it away (shared/alpha.h's rule, as the reference's filter).
bool bvhCutAway(uint cutout, vec2 bary) {
  return cutoutCutAway(BVH_ADDRESSES.cutouts, BVH_ADDRESSES.cutoutTexels, cutout - 1u, bary);
}
#else
#ifdef BVH_CUTOUTS
// Kernels that read the BVH through bindings (the line space's moving meshes) give the cut-outs'
// addresses as BVH_CUTOUTS: (triangles, alpha words).
#include "cutout_test.glsl"
bool bvhCutAway(uint cutout, vec2 bary) { return cutoutCutAway(BVH_CUTOUTS, cutout - 1u, bary); }
#else
bool bvhCutAway(uint cutout, vec2 bary) { return false; }
#endif
layout(std430, binding = BVH_BINDING_NODES) readonly buffer BvhNodes { BvhNode bvhNodes[]; };
layout(std430, binding = BVH_BINDING_TRIANGLES) readonly buffer BvhTriangles { BvhTriangle bvhTriangles[]; };
#endif
#ifndef BVH_NO_COUNTERS
layout(std430, binding = BVH_BINDING_COUNTERS) buffer BvhCounters { uint bvhCounters[BVH_COUNTER_WORDS]; };
#endif

// Statistics of the calling invocation, added to by every traversal (reset by the caller).
uint bvhNodeVisits = 0u;
uint bvhTriangleTests = 0u;

// The computed slab distances may be off by a few ulps; widening the exit distance keeps the box
// test conservative (a box the ray touches is never culled), as in pbrt's robust slab test. The
// builder's padding covers origins lying on a box face, where the exit distance is about zero.
const float kBvhExitScale = 1.0f + 1.0e-6f;

// Whether the ray meets box [lo, hi] within [tMin, tMax]; `enter` gets its entry distance.
bool bvhSlab(vec3 lo, vec3 hi, vec3 origin, vec3 invDir, float tMin, float tMax, out float enter) {
  vec3 t0 = (lo - origin) * invDir;
  vec3 t1 = (hi - origin) * invDir;
  vec3 tNear = min(t0, t1);
  vec3 tFar = max(t0, t1);
  enter = max(max(tNear.x, tNear.y), max(tNear.z, tMin));
  float exit = min(min(tFar.x, tFar.y), min(tFar.z, tMax)) * kBvhExitScale;
  return enter <= exit;
}

// Robust reciprocal direction: zero components become tiny ones so that slab distances stay
// finite (0 * inf would give NaN, whose min/max is undefined).
vec3 bvhInverseDirection(vec3 dir) {
  const float tiny = 1.0e-20f;
  vec3 safe = mix(dir, mix(vec3(tiny), vec3(-tiny), lessThan(dir, vec3(0.0f))), lessThan(abs(dir), vec3(tiny)));
  return 1.0f / safe;
}

// Tests the `count` triangles of a leaf from `first`; a hit shortens tMax (closest hit) and is
// kept in `hit`, unless a cut-out's texture cuts it away there. Returns whether it found one.
bool bvhLeaf(uint first, uint count, vec3 origin, vec3 dir, float tMin, inout float tMax, inout RayHit hit,
             bool anyHit) {
  bool found = false;
  for (uint i = first; i < first + count; ++i) {
    ++bvhTriangleTests;
    BvhTriangle tri = bvhTriangles[i];
    vec2 bary;
    float t = bvhTriangleHit(tri, origin, dir, tMin, tMax, bary);
    if (t < 0.0f) continue;
    if (tri.cutout != 0u && bvhCutAway(tri.cutout, bary)) continue;  // the ray passes through
    hit = RayHit(t, tri.id, 0u, 0u);
    found = true;
    if (anyHit) break;
    tMax = t;  // only nearer hits matter from now on
  }
  return found;
}

// Traversal of the tree rooted at `root`, shared by both queries; anyHit is a constant at every
// call site, so the compiler specialises the loop. Returns the hit (t < 0 and BVH_NO_HIT on a
// miss). The two child slots are handled without loops or indexed locals, which GPUs would
// otherwise spill to memory.
// With BVH_LINE_SPACES (bvh_ls_traverse.glsl included first) and lineSpaces, an inner node that
// has a candidate line space is answered by it (bvhLsAsk) like a leaf instead of being descended.
RayHit bvhTraverse(uint root, vec3 origin, vec3 dir, float tMin, float tMax, bool anyHit, bool lineSpaces) {
  RayHit hit = RayHit(-1.0f, BVH_NO_HIT, 0u, 0u);
#ifdef BVH_LINE_SPACES
  if (lineSpaces && csNodeMap[root] != CS_NONE) {  // D = 0: the root's line space answers alone
    ++bvhNodeVisits;
    bvhLsAsk(csNodeMap[root], origin, dir, tMin, tMax, hit);
    return hit;
  }
#endif
  vec3 invDir = bvhInverseDirection(dir);
  uint stack[BVH_STACK_SIZE];
  uint depth = 0u;
  uint node = root;
  for (;;) {
    ++bvhNodeVisits;
    BvhNode n = bvhNodes[node];
    float enter0, enter1;
    bool go0 = bvhSlab(n.child[0].lo, n.child[0].hi, origin, invDir, tMin, tMax, enter0);
    bool go1 = bvhSlab(n.child[1].lo, n.child[1].hi, origin, invDir, tMin, tMax, enter1);
    // Leaves are tested at once; only inner children go on.
    if (go0 && n.child[0].count > 0u) {
      if (bvhLeaf(n.child[0].index, n.child[0].count, origin, dir, tMin, tMax, hit, anyHit) && anyHit) return hit;
      go0 = false;
    }
    if (go1 && n.child[1].count > 0u) {
      if (bvhLeaf(n.child[1].index, n.child[1].count, origin, dir, tMin, tMax, hit, anyHit) && anyHit) return hit;
      go1 = false;
    }
    go1 = go1 && n.child[1].index != 0u;  // inner index 0 (the static root) marks an empty slot
#ifdef BVH_LINE_SPACES
    if (lineSpaces) {  // inner children with a line space are answered now, the nearer first
      uint ls0 = go0 ? bvhLsChildSpace(n.child[0]) : CS_NONE;
      uint ls1 = go1 ? bvhLsChildSpace(n.child[1]) : CS_NONE;
      bool nearer0 = enter0 <= enter1;
      uint lsA = nearer0 ? ls0 : ls1, lsB = nearer0 ? ls1 : ls0;
      if (lsA != CS_NONE && bvhLsAsk(lsA, origin, dir, tMin, tMax, hit) && anyHit) return hit;
      if (lsB != CS_NONE && bvhLsAsk(lsB, origin, dir, tMin, tMax, hit) && anyHit) return hit;
      go0 = go0 && ls0 == CS_NONE;
      go1 = go1 && ls1 == CS_NONE;
    }
#endif
    if (!anyHit) {
      // A leaf hit may have shortened the ray to before an inner child's entry.
      float limit = tMax * kBvhExitScale;
      go0 = go0 && enter0 <= limit;
      go1 = go1 && enter1 <= limit;
    }
    if (go0 && go1) {
      bool firstNearer = enter0 <= enter1;
      stack[depth++] = firstNearer ? n.child[1].index : n.child[0].index;
      node = firstNearer ? n.child[0].index : n.child[1].index;
    } else if (go0 || go1) {
      node = go0 ? n.child[0].index : n.child[1].index;
    } else {
      if (depth == 0u) break;
      node = stack[--depth];
    }
  }
  return hit;
}

RayHit bvhTraverse(uint root, vec3 origin, vec3 dir, float tMin, float tMax, bool anyHit) {
  return bvhTraverse(root, origin, dir, tMin, tMax, anyHit, false);
}

// The first hit found within [tMin, tMax]: the static tree first (most rays end there), then the
// dynamic tree rooted at dynamicRoot (BVH_NO_TREE: none).
RayHit bvhAnyHitRecord(vec3 origin, vec3 dir, float tMin, float tMax, uint dynamicRoot) {
  RayHit hit = bvhTraverse(0u, origin, dir, tMin, tMax, true);
  if (hit.triangle == BVH_NO_HIT && dynamicRoot != BVH_NO_TREE)
    hit = bvhTraverse(dynamicRoot, origin, dir, tMin, tMax, true);
  return hit;
}

// The nearest hit within [tMin, tMax] in either tree: the dynamic tree only looks before the
// static tree's hit.
RayHit bvhClosestHit(vec3 origin, vec3 dir, float tMin, float tMax, uint dynamicRoot) {
  RayHit hit = bvhTraverse(0u, origin, dir, tMin, tMax, false);
  if (dynamicRoot != BVH_NO_TREE) {
    RayHit moving = bvhTraverse(dynamicRoot, origin, dir, tMin, hit.triangle != BVH_NO_HIT ? hit.t : tMax, false);
    if (moving.triangle != BVH_NO_HIT) hit = moving;
  }
  return hit;
}

#ifndef BVH_NO_COUNTERS
// Adds to a 64-bit counter kept as (low, high) words: the low word's atomic returns its old value,
// and exactly the add that wraps it carries one into the high word.
void bvhAddCounter(uint word, uint value) {
  if (value == 0u) return;
  uint old = atomicAdd(bvhCounters[word], value);
  if (old > 0xffffffffu - value) atomicAdd(bvhCounters[word + 1u], 1u);
}

// Adds this invocation's rays and traversal counts to the counters, one atomic per subgroup and
// counter. Call it from every invocation that has not returned (inactive ones just drop out).
// Per-invocation counts stay far below 2^32 (at most spp rays of a few thousand steps each), and
// so do their subgroup sums; only the running totals need the carry.
void bvhAddCounters(uint rays) {
  uint subgroupRays = subgroupAdd(rays);
  uint subgroupVisits = subgroupAdd(bvhNodeVisits);
  uint subgroupTests = subgroupAdd(bvhTriangleTests);
  if (subgroupElect()) {
    bvhAddCounter(BVH_COUNTER_RAYS, subgroupRays);
    bvhAddCounter(BVH_COUNTER_NODE_VISITS, subgroupVisits);
    bvhAddCounter(BVH_COUNTER_TRIANGLE_TESTS, subgroupTests);
  }
}
#endif  // BVH_NO_COUNTERS
#endif  // PENUMBRA_BVH_TRAVERSE_GLSL
