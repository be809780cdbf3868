// Line-space traversal for shadow rays (Keul et al. 2017, Algorithm 1), included by
// linespace_trace.glsl (not compiled on its own). Declares the three pools and the counters at
// LS_BINDING_*; includers enable GL_KHR_shader_subgroup_basic and _arithmetic (lsAddCounters).
// With LS_EXACT defined (exact mode) it also declares the leaf records, leaf triangle lists and
// triangles, and tests the triangles of the leaf cells instead of answering from the bits alone.
//
// A subdivided node is visited with the ray segment clipped to its cube:
//  - binary mode: if the segment starts or ends inside the cube, its shaft would cover the part
//    of the line beyond the segment (the surface the ray leaves, or what lies behind the light),
//    so the node's line space cannot be used. Above the second-to-last level the node is entered
//    (its children decide); at the second-to-last level it is skipped, as the paper requires: the
//    geometry of the finest node around the shading point casts no shadow (missing contact
//    shadows). Exact mode looks up the shaft of the whole line through the cube instead: a clear
//    bit means nothing in the cube meets the line, so nothing meets the segment either; a set bit
//    enters the node, the start node included;
//  - otherwise the shaft of its entry and exit patches is looked up: bit clear -> nothing in the
//    node can block the ray; bit set -> binary mode: occluded at the second-to-last level (the
//    approximation: the ray need not hit what the shaft meets); else (and in exact mode at every
//    level) its non-empty children along the ray are visited front to back (3D DDA over the N^3
//    grid) with an explicit stack of DDA states. Exact mode's children of a second-to-last-level
//    node are leaf cells: their triangles are tested (triangle_test.glsl, the BVH's test).
// A segment entering and leaving through the same face (it grazes that face) has no shaft; it
// is treated as a set bit, which keeps the answer conservative.
// Front to back means the first leaf cell whose tests find a hit within the cell's own stretch
// of the ray [tIn, tOut] holds the closest hit (a triangle met earlier would have been found in
// the earlier cell that holds the hit point), so lsClosestHit stops there.
//
// With LS_CANDIDATES defined (Keul et al. 2018, 3.2 "Adaptation to NTree"; binary pools only) the
// nodes that have a candidate line space (lsCandidateSpace[node] != CS_NONE) act as leaves: a
// node reached with a set bit (of the whole line's shaft, as in exact mode) is answered by csHit
// instead of being descended; lsCandidateClosestHit stops at the first such answer, the nearest
// (front to back, and csHit's hit lies within the node's stretch of the ray). The includer
// includes candidate_lookup.glsl first (CS_PARAMS, the CS_BINDING_* buffers) and defines
// LS_CANDIDATE_NODE_MAP_BINDING, where the per-node map (N-tree node -> line space or CS_NONE) is.
// Options of the includer: LS_PUSH_DECLARED (it declared push constants with an LsPush named
// lsPush itself), LS_NO_COUNTERS (no counter buffer, no lsAddCounters).
#include "shared/bvh.h"
#include "shared/linespace.h"

layout(std430, binding = LS_BINDING_TREE) readonly buffer LsTree { uint lsTree[]; };
layout(std430, binding = LS_BINDING_NODES) readonly buffer LsNodes { LsNode lsNodes[]; };
layout(std430, binding = LS_BINDING_BITS) readonly buffer LsBits { uint lsBits[]; };
#ifndef LS_NO_COUNTERS
layout(std430, binding = LS_BINDING_COUNTERS) buffer LsCounters { uint lsCounters[LS_COUNTER_WORDS]; };
#endif
#ifndef LS_PUSH_DECLARED
layout(push_constant) uniform LsPushBlock { LsPush lsPush; };
#endif
#ifdef LS_CANDIDATES
layout(std430, binding = LS_CANDIDATE_NODE_MAP_BINDING) readonly buffer LsCandidateMap { uint lsCandidateSpace[]; };
#endif
#ifdef LS_EXACT
#include "triangle_test.glsl"
#include "cutout_test.glsl"
layout(std430, binding = LS_BINDING_LEAVES) readonly buffer LsLeaves { LsLeaf lsLeaves[]; };
layout(std430, binding = LS_BINDING_LEAF_TRIANGLES) readonly buffer LsLeafTriangles { uint lsLeafTriangles[]; };
layout(std430, binding = LS_BINDING_TRIANGLES) readonly buffer LsTriangles { BvhTriangle lsTriangles[]; };
#endif

// Statistics of the calling invocation.
uint lsNodeVisits = 0u;
uint lsTriangleTests = 0u;

#define LS_SKIPPED 0u
#define LS_OCCLUDED 1u
#define LS_DESCEND 2u

// Robust reciprocal (as bvhInverseDirection): tiny components stay finite so slab distances never
// become NaN.
vec3 lsInverseDirection(vec3 dir) {
  const float tiny = 1.0e-20f;
  vec3 safe = mix(dir, mix(vec3(tiny), vec3(-tiny), lessThan(dir, vec3(0.0f))), lessThan(abs(dir), vec3(tiny)));
  return 1.0f / safe;
}

// What to do with subdivided node `index` for the segment origin + t dir, t in [tMin, tMax].
// tIn/tOut: the segment's part inside the node.
// wholeLine (exact mode, and the candidate traversal of every mode): the shaft of the whole line
// through the cube, a set bit always descends; else the binary rules above.
uint lsClassifyAs(uint index, vec3 origin, vec3 dir, vec3 invDir, float tMin, float tMax, bool wholeLine,
                  out float tIn, out float tOut) {
  ++lsNodeVisits;
  LsNode node = lsNodes[index];
  vec3 t0 = (node.position - origin) * invDir;
  vec3 t1 = (node.position + vec3(node.size) - origin) * invDir;
  vec3 tNear = min(t0, t1);
  vec3 tFar = max(t0, t1);
  float enter = max(tNear.x, max(tNear.y, tNear.z));
  float exit = min(tFar.x, min(tFar.y, tFar.z));
  tIn = max(enter, tMin);
  tOut = min(exit, tMax);
  if (tIn > tOut) return LS_SKIPPED;  // the DDA may hand over a cell the segment only grazes
  bool last = node.level + 1u >= lsPush.depth;
  if (!wholeLine && (enter <= tMin || exit >= tMax)) return last ? LS_SKIPPED : LS_DESCEND;  // an end lies inside
  uint axisIn = tNear.x == enter ? 0u : (tNear.y == enter ? 1u : 2u);
  uint axisOut = tFar.x == exit ? 0u : (tFar.y == exit ? 1u : 2u);
  uint faceIn = 2u * axisIn + (lsComponent(invDir, axisIn) > 0.0f ? 0u : 1u);
  uint faceOut = 2u * axisOut + (lsComponent(invDir, axisOut) > 0.0f ? 1u : 0u);
  vec3 localIn = (origin + enter * dir - node.position) / node.size;
  vec3 localOut = (origin + exit * dir - node.position) / node.size;
  uint n = lsPush.n;
  uint shaft = lsShaft(faceIn, lsPatch(localIn, faceIn, n), faceOut, lsPatch(localOut, faceOut, n), n);
  if (shaft != LS_NO_SHAFT) {
    uint word = lsBits[index * lsPush.wordsPerNode + shaft / 32u];
    if ((word & (1u << (shaft % 32u))) == 0u) return LS_SKIPPED;
  }
  return wholeLine || !last ? LS_DESCEND : LS_OCCLUDED;
}

// Steps the DDA past `cell` of `node`'s grid: across the boundary the ray reaches first (at tNext);
// the next cell, or ivec3(-1) when the ray leaves the grid or its segment (exit tOut) there.
ivec3 lsNextCell(LsNode node, ivec3 cell, vec3 origin, vec3 invDir, ivec3 stepDir, float tOut, out float tNext) {
  int n = int(lsPush.n);
  float cellSize = node.size / float(n);
  vec3 boundary = node.position + vec3(cell + max(stepDir, ivec3(0))) * cellSize;
  vec3 tCross = (boundary - origin) * invDir;
  tNext = min(tCross.x, min(tCross.y, tCross.z));
  ivec3 axisMask = tCross.x == tNext ? ivec3(1, 0, 0) : (tCross.y == tNext ? ivec3(0, 1, 0) : ivec3(0, 0, 1));
  ivec3 nextCell = cell + axisMask * stepDir;
  bool leaves = tNext >= tOut || any(lessThan(nextCell, ivec3(0))) || any(greaterThanEqual(nextCell, ivec3(n)));
  return leaves ? ivec3(-1) : nextCell;
}

// The cell of `node`'s grid that holds point p (clamped to the grid).
ivec3 lsCellOf(LsNode node, vec3 p) {
  float n = float(lsPush.n);
  return ivec3(clamp(floor((p - node.position) / node.size * n), vec3(0.0f), vec3(n - 1.0f)));
}

#ifdef LS_EXACT
// Tests the triangles of leaf record `leaf` within [tMin, tMax]; a hit shortens tMax (closest
// hit) and is kept in t and triangle (BvhTriangle.id). Returns whether it found one.
// A triangle overlapping several leaf cells is listed in each; the last four tested by this ray
// (lsTraverse resets them) are not tested again: a miss stays a miss as tMax only shrinks, and a
// hit is already in t. Four scalars, not an array, so no lane indexes memory.
uint lsTested0 = LS_SKIP, lsTested1 = LS_SKIP, lsTested2 = LS_SKIP, lsTested3 = LS_SKIP;

bool lsLeafHit(uint leaf, vec3 origin, vec3 dir, float tMin, inout float tMax, bool anyHit, inout float t,
               inout uint triangle) {
  LsLeaf record = lsLeaves[leaf];
  bool found = false;
  for (uint i = record.first; i < record.first + record.count; ++i) {
    uint index = lsLeafTriangles[i];
    if (index == lsTested0 || index == lsTested1 || index == lsTested2 || index == lsTested3) continue;
    lsTested3 = lsTested2;
    lsTested2 = lsTested1;
    lsTested1 = lsTested0;
    lsTested0 = index;
    ++lsTriangleTests;
    BvhTriangle tri = lsTriangles[index];
    vec2 bary;
    float hit = bvhTriangleHit(tri, origin, dir, tMin, tMax, bary);
    if (hit < 0.0f) continue;
    if (tri.cutout != 0u && cutoutCutAway(lsPush.cutouts, lsPush.cutoutTexels, tri.cutout - 1u, bary)) continue;
    t = hit;
    triangle = tri.id;
    found = true;
    if (anyHit) break;
    tMax = hit;  // only nearer hits matter from now on
  }
  return found;
}
#endif

// The traversal behind lsOccluded, lsClosestHit and lsCandidateClosestHit over the segment
// origin + t dir, t in [tMin, tMax]; anyHit and candidates are constants at every call site.
// Returns whether it found a blocker: in exact mode a triangle (t its distance, the nearest one
// unless anyHit; triangle its BvhTriangle.id), in binary mode a set shaft bit (t = -1, triangle =
// BVH_NO_HIT). With candidates (LS_CANDIDATES), a node that has a candidate line space is
// answered by csHit, like a leaf (front to back: the first node with a hit holds the nearest), and
// one without it or children is passed over.
bool lsTraverse(vec3 origin, vec3 dir, float tMin, float tMax, bool anyHit, bool candidates, out float t,
                out uint triangle) {
  t = -1.0f;
  triangle = BVH_NO_HIT;
#ifdef LS_EXACT
  lsTested0 = lsTested1 = lsTested2 = lsTested3 = LS_SKIP;
#endif
  vec3 invDir = lsInverseDirection(dir);
  // From invDir's sign, so that a zero component (made +tiny) steps towards its far boundary.
  ivec3 stepDir = ivec3(greaterThan(invDir, vec3(0.0f))) * 2 - ivec3(1);
  int n = int(lsPush.n);
  // DDA state per level: the node, the cell next to visit (x < 0: done) and the segment's exit.
  uint frameNode[LS_MAX_DEPTH];
  ivec3 frameCell[LS_MAX_DEPTH];
  float frameOut[LS_MAX_DEPTH];
  float tIn, tOut;
#ifdef LS_EXACT
  const bool wholeLine = true;
#else
  bool wholeLine = candidates;
#endif
  uint root = lsClassifyAs(0u, origin, dir, invDir, tMin, tMax, wholeLine, tIn, tOut);
  if (root != LS_DESCEND) return root == LS_OCCLUDED;
#ifdef LS_CANDIDATES
  vec3 normal;  // csHit's, not used: hits are shaded from their triangle
  if (candidates && lsCandidateSpace[0] != CS_NONE) return csHit(lsCandidateSpace[0], origin, dir, tMin, tMax, t, triangle, normal);
#endif
  int level = 0;
  frameNode[0] = 0u;
  frameCell[0] = lsCellOf(lsNodes[0], origin + tIn * dir);
  frameOut[0] = tOut;
  while (level >= 0) {
    ivec3 cell = frameCell[level];
    if (cell.x < 0) {
      --level;
      continue;
    }
    LsNode node = lsNodes[frameNode[level]];
    float tNext;
    frameCell[level] = lsNextCell(node, cell, origin, invDir, stepDir, frameOut[level], tNext);

    uint child = lsTree[node.children + lsCellIndex(uint(cell.x), uint(cell.y), uint(cell.z), uint(n))];
    if (child == LS_SKIP) continue;
#ifdef LS_EXACT
    if (node.level + 1u >= lsPush.depth) {  // a leaf cell
      bool found = lsLeafHit(child, origin, dir, tMin, tMax, anyHit, t, triangle);
      if (found && anyHit) return true;
      // Every cell before this one has been tested: a hit up to this cell's exit is the nearest.
      if (triangle != BVH_NO_HIT && tMax <= tNext) return true;
      continue;
    }
#endif
    uint result = lsClassifyAs(child, origin, dir, invDir, tMin, tMax, wholeLine, tIn, tOut);
    if (result == LS_OCCLUDED) return true;
    if (result != LS_DESCEND) continue;
#ifdef LS_CANDIDATES
    if (candidates) {
      uint space = lsCandidateSpace[child];
      if (space != CS_NONE) {
        if (csHit(space, origin, dir, tMin, tMax, t, triangle, normal)) return true;
        continue;
      }
      if (lsNodes[child].children == LS_SKIP) continue;
    }
#endif
    ++level;
    frameNode[level] = child;
    frameCell[level] = lsCellOf(lsNodes[child], origin + tIn * dir);
    frameOut[level] = tOut;
  }
  return triangle != BVH_NO_HIT;
}

// Whether the segment origin + t dir, t in [tMin, tMax], is occluded according to the line space
// (exact mode: whether a triangle blocks it, blockerT the distance of the one found; binary mode:
// a set shaft bit at the second-to-last level, blockerT = -1).
bool lsOccluded(vec3 origin, vec3 dir, float tMin, float tMax, out float blockerT) {
  uint triangle;
  return lsTraverse(origin, dir, tMin, tMax, true, false, blockerT, triangle);
}

bool lsOccluded(vec3 origin, vec3 dir, float tMin, float tMax) {
  float blockerT;
  return lsOccluded(origin, dir, tMin, tMax, blockerT);
}

#ifdef LS_EXACT
// The nearest triangle the segment origin + t dir, t in [tMin, tMax], hits: its distance t and
// its BvhTriangle.id (scene-order index); false (t < 0, BVH_NO_HIT) on a miss. Exact mode only.
bool lsClosestHit(vec3 origin, vec3 dir, float tMin, float tMax, out float t, out uint triangle) {
  return lsTraverse(origin, dir, tMin, tMax, false, false, t, triangle);
}
#endif

#ifdef LS_CANDIDATES
// The nearest hit of the segment origin + t dir, t in [tMin, tMax], as the candidate line spaces
// answer it (approximate): t and the candidate's scene-order triangle; false (t < 0, BVH_NO_HIT)
// on a miss.
bool lsCandidateClosestHit(vec3 origin, vec3 dir, float tMin, float tMax, out float t, out uint triangle) {
  return lsTraverse(origin, dir, tMin, tMax, false, true, t, triangle);
}
#endif

#ifndef LS_NO_COUNTERS
// Adds to a 64-bit counter kept as (low, high) words (see bvhAddCounter).
void lsAddCounter(uint word, uint value) {
  if (value == 0u) return;
  uint old = atomicAdd(lsCounters[word], value);
  if (old > 0xffffffffu - value) atomicAdd(lsCounters[word + 1u], 1u);
}

// This invocation's rays, node visits and triangle tests, one atomic per subgroup and counter;
// call it from every invocation that has not returned.
void lsAddCounters(uint rays) {
  uint subgroupRays = subgroupAdd(rays);
  uint subgroupVisits = subgroupAdd(lsNodeVisits);
  uint subgroupTests = subgroupAdd(lsTriangleTests);
  if (subgroupElect()) {
    lsAddCounter(LS_COUNTER_RAYS, subgroupRays);
    lsAddCounter(LS_COUNTER_NODE_VISITS, subgroupVisits);
    lsAddCounter(LS_COUNTER_TRIANGLE_TESTS, subgroupTests);
  }
}
#endif  // LS_NO_COUNTERS
