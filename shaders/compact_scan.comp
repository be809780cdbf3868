#version 450
// Compaction, pass 1 of 3 (see shared/compact.h): each invocation packs the selection of its tile's
// COMPACT_ITEMS pixels into one mask word; the workgroup sums its block's total.
#extension GL_GOOGLE_include_directive : require
#include "shared/compact.h"
layout(local_size_x = COMPACT_GROUP_SIZE) in;
layout(push_constant) uniform Push { CompactPush push; };
layout(binding = COMPACT_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(std430, binding = COMPACT_BINDING_FLAGS) readonly buffer Flags { uint traceFlags[]; };
layout(std430, binding = COMPACT_BINDING_MASK) writeonly buffer Mask { uint mask[]; };
layout(std430, binding = COMPACT_BINDING_BLOCKS) writeonly buffer Blocks { uint blockTotals[]; };
#include "compact_common.glsl"

void main() {
  uint block = blockIndex();
  if (block >= push.blockCount) return;  // tail of the 2D grid: whole workgroups leave together
  uint rank = scanRank();
  uint first = block * COMPACT_BLOCK_PIXELS + rank * COMPACT_ITEMS;
  bool allCovered = (push.mode & COMPACT_MODE_MASK) == COMPACT_ALL_COVERED;
  uint tilesX = compactTilesX(push.width);
  uint bits = 0u;
  for (uint i = 0u; i < COMPACT_ITEMS; ++i) {
    uvec2 pix = compactPixel(first + i, tilesX);
    if (pix.x >= push.width || pix.y >= push.height) continue;
    // A flag on an uncovered pixel is ignored: there is no surface there to shade or trace from.
    if (!allCovered && traceFlags[pix.y * push.width + pix.x] == 0u) continue;
    if (imageLoad(gPosition, ivec2(pix)).w != 0.0) bits |= 1u << i;
  }
  mask[block * COMPACT_GROUP_SIZE + rank] = bits;
  uint total;
  workgroupExclusiveAdd(uint(bitCount(bits)), total);
  if (rank == 0u) blockTotals[block] = total;
}
