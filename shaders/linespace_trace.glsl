// Shadow rays of the line-space tracer, the body of linespace_trace(_exact)(_rq).comp (not
// compiled on its own): one invocation per ShadingPoint of the TraceJob, dispatched indirectly
// from TraceCount. The same samples, ray origins and ray ends as bvh_trace.comp and
// EmbreeTracer::traceShadows (shadow_rays.glsl); only the occlusion test differs (lsOccluded: in
// binary mode an approximation that may only over-darken, apart from the skipped start node; with
// LS_EXACT the triangles of the leaf cells the bits lead to, tested as the BVH tests them).
// Writes visibility[point.pixel] itself.
// Moving meshes are not in the line space; they are traced exactly in the same query, on their own
// BVH, or with LS_MOVING_RAY_QUERY on the driver's acceleration structures over them.
// The dynamic BVH's bindings, set before anything includes shared/bvh.h (which defaults them).
#define BVH_BINDING_NODES LS_BINDING_BVH_NODES
#define BVH_BINDING_TRIANGLES LS_BINDING_BVH_TRIANGLES
#include "shared/trace.h"
#include "shadow_rays.glsl"
#include "linespace_traverse.glsl"
#ifdef LS_MOVING_RAY_QUERY
#define RQ_BINDING_SCENE LS_BINDING_BVH_NODES
#define RQ_BINDING_TRIANGLE_IDS LS_BINDING_BVH_TRIANGLES
#define RQ_NO_COUNTERS
#include "rq_common.glsl"
bool movingOccluded(vec3 origin, vec3 dir, float tMax) {
  return rqTrace(origin, dir, 0.0f, tMax, true).triangle != BVH_NO_HIT;
}
#else
#define BVH_NO_COUNTERS
#define BVH_CUTOUTS lsPush.cutouts, lsPush.cutoutTexels
#include "bvh_traverse.glsl"
bool movingOccluded(vec3 origin, vec3 dir, float tMax) {
  return bvhTraverse(lsPush.dynamicRoot, origin, dir, 0.0f, tMax, true).triangle != BVH_NO_HIT;
}
#endif
layout(local_size_x = TRACE_GROUP_SIZE) in;
layout(std430, binding = LS_BINDING_TRACE_JOB) readonly buffer Count { TraceCount traceCount; };
layout(std430, binding = LS_BINDING_TRACE_JOB + 1) readonly buffer Frame { FrameData frame; };
layout(std430, binding = LS_BINDING_TRACE_JOB + 2) writeonly buffer Visibility { float visibility[]; };
#include "trace_points.glsl"

// Binary mode: the line space answers from where the ray is startOffset above the surface on (see
// LsPush); a shaft says that something blocks, not where: the blocker distance is unknown (-1).
// Exact mode takes the whole segment from t = 0, as bvh_trace.comp does (the ray origin's offset
// keeps the surface from shadowing itself), and knows the blocker's distance. The moving meshes'
// trace is exact in both, so it takes the whole segment.
bool shadowOccluded(ShadingPoint point, vec3 origin, vec3 dir, float tMax, out float blockerT) {
#ifdef LS_EXACT
  float tStart = 0.0f;
#else
  float tStart = min(lsPush.startOffset / max(dot(dir, point.normal), 1e-3), tMax);
#endif
  if (lsOccluded(origin, dir, tStart, tMax, blockerT)) return true;
  blockerT = -1.0f;
  return lsPush.dynamicRoot != BVH_NO_TREE && movingOccluded(origin, dir, tMax);
}

void main() {
  uint rays = 0u;
  traceShadows(rays);
#ifndef LS_MOVING_RAY_QUERY
  lsNodeVisits += bvhNodeVisits;  // the dynamic BVH's visits and tests count too
  lsTriangleTests += bvhTriangleTests;
#endif
  lsAddCounters(rays);
}
