// The candidate line space (Keul et al. 2018, 3) as the GPU reads it: per chosen box of a
// hierarchy (BVH inner nodes at depth D, N-tree nodes) one representative triangle per directed
// shaft, in the paper's sparse layout. Built by raytrace/candidate_line_space, read by
// candidate_lookup.glsl (csHit) and bvh_ls_traverse.glsl (BVH closest hit with line-space nodes).
//
// Faces and patches as in shared/linespace.h: face = 2 * axis + side, patch (pu, pv) on axes
// u = (a + 1) % 3, v = (a + 2) % 3, numbered pu + N * pv (lsPatch). A box need not be a cube: the
// patches of a face split its two extents into N equal parts each.
// Shafts are directed (entry patch, exit patch on another face): 30 * N^4 per box, numbered by
// csShaft.
// Sparse layout: per box csWordsPerBox(N) 32-bit words of bits (bit = shaft filled) from the box's
// wordBase; one offset per word (the exclusive prefix sum of the popcounts over all boxes' words);
// the filled shafts' triangle indices (scene order) packed in that order. Shaft s of a box:
// word w = wordBase + s / 32, bit b = s % 32, candidate = candidates[csDataIndex(offsets[w],
// bits[w], b)] when the bit is set.
#ifndef PENUMBRA_SHARED_CANDIDATES_H
#define PENUMBRA_SHARED_CANDIDATES_H
#include "shared/bvh.h"
#include "shared/glsl_cpp.h"
PN_BEGIN

#define CS_NONE 0xffffffffu  // no line space at this node / empty shaft / no shaft

// Bindings of the line-space buffers; an including kernel may define any of them first to move
// them. All are std430 storage buffers, read only:
//   CS_BINDING_BOXES            CsBox csBoxes[]            one per line space
//   CS_BINDING_BITS             uint csBits[]              csWordsPerBox(N) per line space
//   CS_BINDING_OFFSETS          uint csOffsets[]           one per word of csBits
//   CS_BINDING_NODE_MAP         uint csNodeMap[]           per BVH node: its line space or CS_NONE
//                                                          (bvh_ls_traverse.glsl only)
// The packed candidates (scene-order triangle indices), the largest by far, and the scene's
// triangles (SceneTriangle) are read through their buffers' device addresses (CsParams), so that
// they are not held to one binding's range (128 MiB on lavapipe): the includer enables
// GL_EXT_buffer_reference and _uvec2.
#ifndef CS_BINDING_BOXES
#define CS_BINDING_BOXES 5
#endif
#ifndef CS_BINDING_BITS
#define CS_BINDING_BITS 6
#endif
#ifndef CS_BINDING_OFFSETS
#define CS_BINDING_OFFSETS 7
#endif
#ifndef CS_BINDING_NODE_MAP
#define CS_BINDING_NODE_MAP 9
#endif

// The N-tree variant's bindings (indirect_ntree_ls.comp, beside the line space's LS_BINDING_*):
// the same buffers, the node map per N-tree node; CandidateBuffers::kNTreeBindings on the C++ side.
#define CS_NTREE_BINDING_BOXES 4
#define CS_NTREE_BINDING_BITS 5
#define CS_NTREE_BINDING_OFFSETS 6
#define CS_NTREE_BINDING_NODE_MAP 10

// Counters of candidate_rays.comp beside shared/bvh.h's (rays, node visits, triangle tests), as
// (low, high) words in the same BVH_COUNTER_WORDS buffer: the candidate (plane) tests.
#define CS_COUNTER_CANDIDATE_TESTS 6u

// One line space's box, std430 32 bytes.
struct CsBox {
  vec3 lo;
  uint wordBase;  // its first word in csBits / csOffsets
  vec3 hi;
  uint node;      // the node it belongs to in its hierarchy (BVH node or N-tree node index)
};

// What csHit needs besides the buffers, 32 bytes: the includer puts one in its push constants (or
// a uniform) and defines CS_PARAMS to name it before including candidate_lookup.glsl.
struct CsParams {
  uint n;                  // line-space resolution N (LS_MIN_N..LS_MAX_N)
  float cosMaxDeviation;   // cos of the largest angle between the extrapolated vertex normal and the
                           // candidate's face normal at which a plane hit is kept; -1 keeps all
  uvec2 candidates;        // device address (low, high) of the packed candidates (uint[])
  uvec2 triangles;         // device address of the scene's triangles (SceneTriangle[], scene order)
  uint pad0, pad1;
};

// Modes of candidate_rays.comp.
#define CS_MODE_BVH_LS 0u     // BVH closest hit, nodes with a line space answered by csHit
#define CS_MODE_BVH_EXACT 1u  // the same BVH, every node descended (the exact reference on the GPU)
#define CS_MODE_BOX 2u        // csHit on line space `box` alone

// Push constants of candidate_rays.comp, 80 bytes.
struct CsRaysPush {
  BvhAddresses bvh;  // the BVH's node and triangle buffers (shared/bvh.h)
  CsParams cs;
  uint first;  // first ray of this dispatch
  uint count;  // rays in this dispatch
  uint mode;   // CS_MODE_*
  uint box;    // CS_MODE_BOX: the line space to ask
};

// RayHit (shared/bvh.h) as candidate_rays.comp fills it: t and triangle as usual (t < 0 and
// BVH_NO_HIT on a miss), pad0 the hit's shading normal (packSnorm2x16(octahedralEncode(n)), the
// vertex normals interpolated, or for a candidate extrapolated, at the hit; facing the ray's
// origin), pad1 CS_HIT_* flags.
#define CS_HIT_FROM_LINE_SPACE 1u

PN_FN uint csShaftCount(uint n) { return 30u * n * n * n * n; }
PN_FN uint csWordsPerBox(uint n) { return (csShaftCount(n) + 31u) / 32u; }

// Directed shaft from patch patchIn of face faceIn to patch patchOut of face faceOut != faceIn.
PN_FN uint csShaft(uint faceIn, uint patchIn, uint faceOut, uint patchOut, uint n) {
  uint n2 = n * n;
  return (faceIn * 5u + faceOut - (faceOut > faceIn ? 1u : 0u)) * n2 * n2 + patchIn * n2 + patchOut;
}

// Index into the packed candidates of the filled shaft at bit `bit` of word `word` whose offset is
// `offset`: the filled shafts before it in this word follow the word's first.
PN_FN uint csDataIndex(uint offset, uint word, uint bit) {
  return offset + uint(bitCount(word & ((1u << bit) - 1u)));
}

PN_END
#endif
