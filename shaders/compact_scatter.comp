#version 450
// Compaction, pass 3 of 3 (see shared/compact.h): each invocation finds where its selected pixels
// go (block offset + workgroup scan of the mask words' bit counts) and writes their ShadingPoints
// in tile order; only selected pixels touch the G-buffer.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#include "shared/compact.h"
#include "shared/frame.h"
#include "shared/shading_point.h"
layout(local_size_x = COMPACT_GROUP_SIZE) in;
layout(push_constant) uniform Push { CompactPush push; };
layout(binding = COMPACT_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(binding = COMPACT_BINDING_NORMAL, rgba32f) uniform readonly image2D gNormal;
layout(std430, binding = COMPACT_BINDING_RAYMAX) readonly buffer RayMax { float rayMax[]; };
layout(std430, binding = COMPACT_BINDING_FRAME) readonly buffer Frame { FrameData frame; };
layout(std430, binding = COMPACT_BINDING_MASK) readonly buffer Mask { uint mask[]; };
layout(std430, binding = COMPACT_BINDING_BLOCKS) readonly buffer Blocks { uint blockOffsets[]; };
#include "point_list.glsl"
#include "compact_common.glsl"

void main() {
  uint block = blockIndex();
  if (block >= push.blockCount) return;  // tail of the 2D grid: whole workgroups leave together
  uint rank = scanRank();
  uint bits = mask[block * COMPACT_GROUP_SIZE + rank];
  uint total;
  uint slot = blockOffsets[block] + workgroupExclusiveAdd(uint(bitCount(bits)), total);
  uint first = block * COMPACT_BLOCK_PIXELS + rank * COMPACT_ITEMS;
  uint spp = frame.spp;
  uint tilesX = compactTilesX(push.width);
  while (bits != 0u) {  // set bits in ascending order = list order
    ivec2 pix = ivec2(compactPixel(first + uint(findLSB(bits)), tilesX));
    bits &= bits - 1u;
    uint p = uint(pix.y) * push.width + uint(pix.x);
    ShadingPoint point;
    point.position = imageLoad(gPosition, pix).xyz;
    point.pixel = p;
    point.normal = imageLoad(gNormal, pix).xyz;
    point.spp = spp;
    point.rayMax = rayMax[p];
    point.pad0 = 0u;
    point.pad1 = 0u;
    point.pad2 = 0u;
    pointList[slot++] = point;
  }
}
