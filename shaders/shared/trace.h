// The contract between compaction and the tracers: a dense list of ShadingPoints, its count and
// the indirect dispatch size of a trace kernel; tracers write visibility[point.pixel] directly
// (write-back fused into the trace).
#ifndef PENUMBRA_SHARED_TRACE_H
#define PENUMBRA_SHARED_TRACE_H
#include "shared/glsl_cpp.h"
PN_BEGIN

#define TRACE_GROUP_SIZE 64  // invocations per workgroup of every trace kernel (one point each)

// Every shadow-ray kernel also binds the G-buffer (rgba32f storage images), read when it traces in
// place (FrameData::traceInPlace: frt on a GPU tracer, no compaction; trace_points.glsl).
#define TRACE_BINDING_POSITION 10
#define TRACE_BINDING_NORMAL 11

// std430, 16 bytes. groupsX/Y/Z is a VkDispatchIndirectCommand at byte offset 4.
struct TraceCount {
  uint count;    // valid points
  uint groupsX;  // ceil(count / TRACE_GROUP_SIZE)
  uint groupsY;  // 1
  uint groupsZ;  // 1
};

PN_END
#endif
