// Compaction (hybrid/compact_pass): per-pixel trace flags -> dense, tile-ordered ShadingPoints.
// Pixels are enumerated in tiles of COMPACT_TILE_W x COMPACT_TILE_H (one mask word, 32 pixels), the
// tiles row by row, so that neighbouring points in the list - one warp of the trace kernel - come
// from neighbouring pixels and share their BVH nodes (coherent ray order; compactPixel).
// Three dispatches, reduce-then-scan:
//   compact_scan    one workgroup per block of COMPACT_BLOCK_PIXELS items: each invocation packs
//                   its tile (COMPACT_ITEMS pixels) into a selection bitmask word, the group
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
#define COMPACT_ITEMS 32        // pixels per invocation: one tile, one selection mask word
#define COMPACT_TILE_W 8
#define COMPACT_TILE_H 4
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
  uint width;       // of the image
  uint height;
  uint blockCount;  // ceil(tiles * COMPACT_ITEMS / COMPACT_BLOCK_PIXELS)
};

// Tiles per image row.
PN_FN uint compactTilesX(uint width) { return (width + COMPACT_TILE_W - 1u) / COMPACT_TILE_W; }

// List items of a width x height image: whole tiles.
PN_FN uint compactItems(uint width, uint height) {
  return compactTilesX(width) * ((height + COMPACT_TILE_H - 1u) / COMPACT_TILE_H) * COMPACT_ITEMS;
}

// The pixel (x, y) of list item `item` (tile item / COMPACT_ITEMS, row-major within the tile); it
// may lie past the image's right or bottom edge in the last tile column or row.
PN_FN uvec2 compactPixel(uint item, uint tilesX) {
  uint tile = item / COMPACT_ITEMS;
  uint lane = item % COMPACT_ITEMS;
  return uvec2((tile % tilesX) * COMPACT_TILE_W + lane % COMPACT_TILE_W, (tile / tilesX) * COMPACT_TILE_H + lane / COMPACT_TILE_W);
}

PN_END
#endif
