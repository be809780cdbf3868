// The shading points of a shadow-ray kernel (after `frame` and `traceCount` are declared; the
// kernel enables GL_EXT_buffer_reference and _uvec2 for point_list.glsl):
// the compacted list, or - when the frame traces in place (frt on a GPU tracer) - every covered
// pixel of FrameData's light rectangle read from the G-buffer, enumerated in the compaction's tile
// order so that a warp still traces neighbouring pixels. The dispatch covers traceCount.groupsX
// groups either way.
#include "shared/compact.h"
#include "shared/trace.h"
#include "point_list.glsl"
layout(binding = TRACE_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(binding = TRACE_BINDING_NORMAL, rgba32f) uniform readonly image2D gNormal;

// This invocation's point: dispatches wider than one row of workgroups (an in-place trace of a
// frame over 4M pixels) continue in further rows.
uint tracePointIndex() {
  return (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * TRACE_GROUP_SIZE + gl_LocalInvocationID.x;
}

// The index-th point, or false when there is none (past the list, off the image, or sky).
bool tracePoint(uint index, out ShadingPoint point) {
  if (frame.traceInPlace == 0u) {
    if (index >= traceCount.count || index >= frame.traceCapacity) return false;  // the host refuses an overfull list
    point = pointList[index];
    return true;
  }
  uvec2 lo = frame.lightRectMin, hi = frame.lightRectMax;
  if (hi == uvec2(0u)) hi = uvec2(frame.width, frame.height);
  uvec2 pix = lo + compactPixel(index, compactTilesX(hi.x - lo.x));
  if (pix.x >= hi.x || pix.y >= hi.y) return false;
  vec4 position = imageLoad(gPosition, ivec2(pix));
  if (position.w == 0.0) return false;
  point.position = position.xyz;
  point.pixel = pix.y * frame.width + pix.x;
  point.normal = imageLoad(gNormal, ivec2(pix)).xyz;
  point.spp = frame.spp;
  point.rayMax = 0.0;
  point.pad0 = point.pad1 = point.pad2 = 0u;
  return true;
}
