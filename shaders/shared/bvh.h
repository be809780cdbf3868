// The GPU BVH (raytrace/bvh_builder) as the traversal kernels read it, and the generic ray
// interface of bvh_rays.comp. Binary nodes hold both children's boxes (Aila & Laine 2009), so one
// 64-byte fetch decides which children a ray enters.
#ifndef PENUMBRA_SHARED_BVH_H
#define PENUMBRA_SHARED_BVH_H
#include "shared/glsl_cpp.h"
PN_BEGIN

// Entries of the per-invocation traversal stack. A push happens only at a node whose two children
// are inner nodes and both entered, so depth-1 entries suffice; the builder caps the depth.
#define BVH_STACK_SIZE 40
#define BVH_GROUP_SIZE 64      // bvh_rays.comp invocations per workgroup (one ray each)
#define BVH_NO_HIT 0xffffffffu  // RayHit.triangle of a miss (its t is then negative)

// Bindings every BVH kernel shares; the kernel's own buffers follow. A kernel that traces a BVH
// beside its own structure (linespace_trace.comp) defines them first to move them.
#ifndef BVH_BINDING_NODES
#define BVH_BINDING_NODES 0
#endif
#ifndef BVH_BINDING_TRIANGLES
#define BVH_BINDING_TRIANGLES 1
#endif
#ifndef BVH_BINDING_COUNTERS
#define BVH_BINDING_COUNTERS 2
#endif
// The shadow-ray kernels' job (bvh_trace.comp, rq_trace.comp): TraceJob::addTo's count, frame and
// visibility at this binding and the two after it. The generic-ray kernels' (bvh_rays.comp,
// rq_rays.comp, candidate_rays.comp) queries and hits.
#define BVH_BINDING_TRACE_JOB 3
#define BVH_BINDING_QUERIES 3
#define BVH_BINDING_HITS 4

// Two trees share the node and triangle buffers (raytrace/bvh_tracer.h): the static scene's,
// rooted at node 0, and, in scenes with moving meshes, the dynamic meshes' tree after it, whose
// root the kernels get by push constant (BVH_NO_TREE: none; 0 can never be a second root).
#define BVH_NO_TREE 0u

// One child slot, std430 32 bytes. count == 0: `index` is an inner node (never 0, the root, so
// index == 0 && count == 0 marks an empty slot: only the root of a one-leaf tree has one).
// count > 0: a leaf of `count` triangles starting at triangle `index`.
struct BvhChild {
  vec3 lo;
  uint index;
  vec3 hi;
  uint count;
};

// std430, 64 bytes: the two child slots, boxes conservatively padded by the builder.
struct BvhNode {
  BvhChild child[2];
};

// std430, 48 bytes. Vertices rather than v0 + edges: the watertight edge test needs the original
// vertex values, so that a shared edge gives exactly opposite answers in its two triangles.
struct BvhTriangle {
  vec3 v0;
  uint id;  // triangle index in scene order (meshes in order, triangles in order within each)
  vec3 v1;
  uint cutout;  // 0: opaque; else alpha-tested, 1 + its CutoutTriangle's index (shared/alpha.h)
  vec3 v2;
  uint pad1;
};

// Counters the kernels add to: each a 64-bit value as two 32-bit words (low, high), carried by
// hand so that no 64-bit atomics are needed; [BVH_COUNTER_WORDS] uint in total.
#define BVH_COUNTER_RAYS 0u
#define BVH_COUNTER_NODE_VISITS 2u
#define BVH_COUNTER_TRIANGLE_TESTS 4u
#define BVH_COUNTER_WORDS 8u

// Generic ray of bvh_rays.comp, std430 32 bytes. Hits count for t in [tMin, tMax].
struct RayQuery {
  vec3 origin;
  float tMin;
  vec3 direction;  // need not be unit; t is in units of its length
  float tMax;
};

// std430, 16 bytes. Miss: t < 0 and triangle == BVH_NO_HIT. Closest-hit: the nearest hit.
// Any-hit: the first hit the traversal found, which need not be the nearest.
struct RayHit {
  float t;
  uint triangle;  // BvhTriangle.id
  uint pad0, pad1;
};

// Where bvh_trace.comp and bvh_rays.comp find the trees: the device addresses of the node and
// triangle buffers, and of the cut-out triangles and their textures' alpha words (shared/alpha.h),
// each as (low, high) 32-bit halves. Read through addresses, a tree is bounded by what one buffer
// may hold (2 GiB on lavapipe), not by one binding's range (128 MiB).
struct BvhAddresses {
  uvec2 nodes;
  uvec2 triangles;
  uvec2 cutouts;
  uvec2 cutoutTexels;
};

// Push constants of bvh_rays.comp, 48 bytes.
struct BvhRaysPush {
  BvhAddresses bvh;
  uint first;        // first ray of this dispatch
  uint count;        // rays in this dispatch
  uint anyHit;       // 1: stop at the first hit; 0: closest hit
  uint dynamicRoot;  // root node of the dynamic tree, or BVH_NO_TREE
};

// Push constants of bvh_trace.comp, 48 bytes.
struct BvhTracePush {
  BvhAddresses bvh;
  uint dynamicRoot;  // root node of the dynamic tree, or BVH_NO_TREE
  uint pad0, pad1, pad2;
};

PN_END
#endif
