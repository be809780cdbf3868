#version 450
// Shadow rays of the line-space tracer: one invocation per ShadingPoint of the TraceJob,
// dispatched indirectly from TraceCount. The same samples, ray origins and ray ends as
// bvh_trace.comp and EmbreeTracer::traceShadows (shadow_rays.glsl); only the occlusion test differs (lsOccluded,
// an approximation that may only over-darken, apart from the skipped start node). Writes
// visibility[point.pixel] itself.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "shared/trace.h"
#include "shadow_rays.glsl"
#include "linespace_traverse.glsl"
// Moving meshes are not in the line space; their own BVH is traced in the same query.
#define BVH_BINDING_NODES LS_BINDING_BVH_NODES
#define BVH_BINDING_TRIANGLES LS_BINDING_BVH_TRIANGLES
#define BVH_NO_COUNTERS
#include "bvh_traverse.glsl"
layout(local_size_x = TRACE_GROUP_SIZE) in;
layout(std430, binding = 4) readonly buffer Points { ShadingPoint points[]; };
layout(std430, binding = 5) readonly buffer Count { TraceCount traceCount; };
layout(std430, binding = 6) readonly buffer Frame { FrameData frame; };
layout(std430, binding = 7) writeonly buffer Visibility { float visibility[]; };

// The line space answers from where the ray is startOffset above the surface on (see LsPush); the
// dynamic BVH is exact, so it takes the whole segment, as bvh_trace.comp does.
bool shadowOccluded(ShadingPoint point, vec3 origin, vec3 dir, float tMax) {
  float tStart = min(lsPush.startOffset / max(dot(dir, point.normal), 1e-3), tMax);
  if (lsOccluded(origin, dir, tStart, tMax)) return true;
  return lsPush.dynamicRoot != BVH_NO_TREE &&
         bvhTraverse(lsPush.dynamicRoot, origin, dir, 0.0f, tMax, true).triangle != BVH_NO_HIT;
}

void main() {
  uint index = gl_GlobalInvocationID.x;
  uint rays = 0u;
  if (index < traceCount.count) {
    ShadingPoint point = points[index];
    visibility[point.pixel] = shadowVisibility(point, frame.light, rays);
  }
  lsNodeVisits += bvhNodeVisits;  // the dynamic BVH's visits count as traversal steps too
  lsAddCounters(rays);
}
