#version 450
// Compaction, pass 2 of 3 (see shared/compact.h), one workgroup: block totals -> exclusive block
// offsets in place, plus the point count and the trace kernel's indirect dispatch size.
// Each invocation owns a contiguous run of ceil(blockCount / COMPACT_GROUP_SIZE) blocks, so any
// block count is handled by one dispatch (runs of 128 at 16384^2 pixels).
#extension GL_GOOGLE_include_directive : require
#include "shared/compact.h"
#include "shared/trace.h"
layout(local_size_x = COMPACT_GROUP_SIZE) in;
layout(push_constant) uniform Push { CompactPush push; };
layout(std430, binding = COMPACT_BINDING_BLOCKS) buffer Blocks { uint blocks[]; };
layout(std430, binding = COMPACT_BINDING_COUNT) writeonly buffer Count { TraceCount traceCount; };
#include "compact_common.glsl"

void main() {
  uint rank = scanRank();
  uint run = (push.blockCount + COMPACT_GROUP_SIZE - 1u) / COMPACT_GROUP_SIZE;
  uint begin = min(rank * run, push.blockCount);
  uint end = min(begin + run, push.blockCount);
  uint sum = 0u;
  for (uint b = begin; b < end; ++b) sum += blocks[b];
  uint total;
  uint offset = workgroupExclusiveAdd(sum, total);
  for (uint b = begin; b < end; ++b) {
    uint n = blocks[b];
    blocks[b] = offset;
    offset += n;
  }
  if (rank == 0u) traceCount = TraceCount(total, (total + TRACE_GROUP_SIZE - 1u) / TRACE_GROUP_SIZE, 1u, 1u);
}
