// Compaction (hybrid/compact_pass): per-pixel trace flags -> dense, pixel-ordered ShadingPoints.
// Three dispatches, reduce-then-scan:
//   compact_scan    one workgroup per block of COMPACT_BLOCK_PIXELS pixels: each invocation packs
//                   its COMPACT_ITEMS consecutive pixels into a selection bitmask word, the group
//                   reduces the bit counts to the block's total
//   compact_blocks  one workgroup: exclusive scan of the block totals (in place), the count and
//                   the indirect dispatch size of the trace kernel
//   compact_scatter one workgroup per block: workgroup exclusive scan of the mask words' bit
//                   counts, then every selected pixel writes its ShadingPoint
#ifndef PENUMBRA_SHARED_COMPACT_H
#define PENUMBRA_SHARED_COMPACT_H
#include "shared/glsl_cpp.h"
PN_BEGIN

#define COMPACT_GROUP_SIZE 256  // invocations per workgroup of every compaction dispatch
#define COMPACT_ITEMS 32        // consecutive pixels per invocation: one selection mask word
#define COMPACT_BLOCK_PIXELS (COMPACT_GROUP_SIZE * COMPACT_ITEMS)  // 8192

#define COMPACT_FLAGGED 0u      // pixels with traceFlags[pixel] != 0 (srt)
#define COMPACT_ALL_COVERED 1u  // every covered pixel (frt)
#define COMPACT_MODE_MASK 0xffu
// Option bit or'ed into the mode: scan in shared memory only, never with subgroup arithmetic.
// The shaders fall back to it by themselves when subgroups do not tile the workgroup exactly;
// tests set it to check that path on devices where they do.
#define COMPACT_SHARED_SCAN 0x100u

// Bindings, for all three pipelines (unused ones are simply not declared by a shader).
#define COMPACT_BINDING_POSITION 0  // rgba32f storage image, w = coverage
#define COMPACT_BINDING_NORMAL 1    // rgba32f storage image
#define COMPACT_BINDING_FLAGS 2     // uint[pixelCount]
#define COMPACT_BINDING_RAYMAX 3    // float[pixelCount]
#define COMPACT_BINDING_FRAME 4     // FrameData
#define COMPACT_BINDING_MASK 5      // uint[blockCount * COMPACT_GROUP_SIZE]
#define COMPACT_BINDING_BLOCKS 6    // uint[blockCount]: block totals, then exclusive offsets
#define COMPACT_BINDING_POINTS 7    // ShadingPoint[pixelCount]
#define COMPACT_BINDING_COUNT 8     // TraceCount

struct CompactPush {
  uint mode;        // COMPACT_FLAGGED / COMPACT_ALL_COVERED, optionally | COMPACT_SHARED_SCAN
  uint pixelCount;  // width * height
  uint width;       // pixel index -> (x, y)
  uint blockCount;  // ceil(pixelCount / COMPACT_BLOCK_PIXELS)
};

PN_END
#endif
