// The binary line space on an N-tree (Keul et al. 2017) as the GPU reads it, and the one canonical
// numbering of cells, faces, patches and shafts that the CPU builder (raytrace/shaft_table,
// raytrace/line_space) and the traversal (linespace_traverse.glsl) share.
//
// Cells: a subdivided node of edge `size` at `position` (its low corner) has N^3 children, cell
// (i, j, k) at position + (i, j, k) * size / N, numbered i + N * (j + N * k).
// Faces: face = 2 * axis + side, side 0 the low face (coordinate 0), side 1 the high one.
// Patches: face f (axis a) is split into N x N patches along the other two axes u = (a + 1) % 3,
// v = (a + 2) % 3; patch (pu, pv) is numbered pu + N * pv.
// Shafts: the convex hull of two patches on different faces, unordered (symmetric), 15 * N^4 per
// node: shaft = lsFacePair(fa, fb) * N^4 + patchA * N^2 + patchB with fa < fb.
#ifndef PENUMBRA_SHARED_LINESPACE_H
#define PENUMBRA_SHARED_LINESPACE_H
#include "shared/glsl_cpp.h"
PN_BEGIN

#define LS_MIN_N 4u
#define LS_MAX_N 10u
#define LS_MIN_DEPTH 2u
#define LS_MAX_DEPTH 4u
// Tree pool entry of a child that is not subdivided (empty, or a leaf cell at the last level), and
// LsNode.children of a node without a children group (the second-to-last level in binary mode).
// Exact mode (LineSpaceSettings::Shadows::Exact) gives second-to-last-level nodes a children group
// too, whose entries are LsLeaf indices (LS_SKIP: an empty cell).
#define LS_SKIP 0xffffffffu
#define LS_NO_SHAFT 0xffffffffu  // a segment that enters and leaves through the same face

#define LS_BINDING_TREE 0
#define LS_BINDING_NODES 1
#define LS_BINDING_BITS 2
#define LS_BINDING_COUNTERS 3
#define LS_BINDING_TRACE_JOB 4  // TraceJob::addTo's count, frame and visibility: 4, 5, 6
// Exact mode only (LS_EXACT kernels): leaf records, their packed triangle index lists, and the
// static triangles in BvhTriangle format (scene-order ids), indexed by the lists.
#define LS_BINDING_LEAVES 12
#define LS_BINDING_LEAF_TRIANGLES 13
#define LS_BINDING_TRIANGLES 14

// Counters as in shared/bvh.h: 64-bit values as (low, high) 32-bit words.
#define LS_COUNTER_RAYS 0u
#define LS_COUNTER_NODE_VISITS 2u
#define LS_COUNTER_TRIANGLE_TESTS 4u
#define LS_COUNTER_WORDS 6u

// Node pool entry (subdivided nodes only; node 0 is the root), std430 32 bytes. Node i's line
// space is lsBits[i * lsWordsPerNode(N) ...].
struct LsNode {
  vec3 position;  // low corner, world space
  float size;     // edge length of the cube
  uint children;  // first of its N^3 tree-pool entries, or LS_SKIP (second-to-last level)
  uint level;     // root 0; nodes at level depth - 1 are the second-to-last level
  uint pad0, pad1;
};

// Leaf record (exact mode), std430 8 bytes: a non-empty leaf cell's triangles are
// lsLeafTriangles[first .. first + count), indices into the triangle pool.
struct LsLeaf {
  uint first;
  uint count;
};

// The dynamic meshes' BVH that linespace_trace.comp traces beside the line space (two-level: the
// line space holds the static meshes only); its nodes and triangles at these bindings.
#define LS_BINDING_BVH_NODES 8
#define LS_BINDING_BVH_TRIANGLES 9

// Push constants of linespace_trace.comp, 48 bytes.
struct LsPush {
  uint n;             // branching factor N
  uint depth;         // maximum depth d: leaves at level d, subdivided nodes at levels 0 .. d-1
  uint wordsPerNode;  // lsWordsPerNode(n)
  float startOffset;  // world units: occluders closer to the surface along the ray are ignored (binary mode only)
  uint dynamicRoot;   // root node of the dynamic BVH, or 0 (BVH_NO_TREE): no moving meshes
  uint pad0;
  uvec2 cutouts;      // (low, high) addresses of the CutoutTriangles and the alpha words (core/cutouts.h),
  uvec2 cutoutTexels; // which exact mode and the moving meshes' BVH test (binary mode: cut-outs are solid)
  uint pad1, pad2;
};

PN_FN uint lsShaftCount(uint n) { return 15u * n * n * n * n; }

// 32-bit words of one node's line space: whole 64-bit words, as the builder ORs them.
PN_FN uint lsWordsPerNode(uint n) { return ((lsShaftCount(n) + 63u) / 64u) * 2u; }

PN_FN uint lsCellIndex(uint i, uint j, uint k, uint n) { return i + n * (j + n * k); }

// Index 0..14 of the unordered pair of different faces fa < fb, row by row.
PN_FN uint lsFacePair(uint fa, uint fb) { return fa * 5u - (fa * (fa - 1u)) / 2u + (fb - fa - 1u); }

// Component i of v without indexing by a variable (which GPU compilers may turn into a local
// array in memory).
PN_FN float lsComponent(vec3 v, uint i) { return i == 0u ? v.x : (i == 1u ? v.y : v.z); }

// The patch of `face` that holds `local`, a point in node coordinates ([0, 1]^3), clamped so
// that points on the node's edges and a little outside still find one.
PN_FN uint lsPatch(vec3 local, uint face, uint n) {
  uint axis = face / 2u;
  float fu = lsComponent(local, (axis + 1u) % 3u) * float(n);
  float fv = lsComponent(local, (axis + 2u) % 3u) * float(n);
  uint pu = uint(clamp(floor(fu), 0.0f, float(n - 1u)));
  uint pv = uint(clamp(floor(fv), 0.0f, float(n - 1u)));
  return pu + n * pv;
}

// The shaft joining patch pa of face fa and patch pb of face fb (either order), or LS_NO_SHAFT
// when the faces are the same.
PN_FN uint lsShaft(uint fa, uint pa, uint fb, uint pb, uint n) {
  if (fa == fb) return LS_NO_SHAFT;
  uint n2 = n * n;
  if (fa < fb) return lsFacePair(fa, fb) * n2 * n2 + pa * n2 + pb;
  return lsFacePair(fb, fa) * n2 * n2 + pb * n2 + pa;
}

PN_END
#endif
