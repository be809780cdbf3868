// Inline ray queries against the scene's top-level acceleration structure
// (raytrace/acceleration_structures.h), included by rq_trace.comp, rq_rays.comp and
// linespace_trace_rq.comp. Every instance is opaque with culling off, so no candidate needs the
// shader's decision: the proceed loop runs the traversal to its end. Includers enable
// GL_EXT_ray_query and subgroup arithmetic.
#include "shared/ray_query.h"

layout(binding = RQ_BINDING_SCENE) uniform accelerationStructureEXT rqScene;
// Per instance where its ids start, then the scene-order id of each triangle in build order.
layout(std430, binding = RQ_BINDING_TRIANGLE_IDS) readonly buffer RqTriangleIds { uint rqTriangleIds[]; };
#ifndef RQ_NO_COUNTERS
layout(std430, binding = RQ_BINDING_COUNTERS) buffer RqCounters { uint rqCounters[BVH_COUNTER_WORDS]; };
#endif

// The nearest hit within [tMin, tMax], or with anyHit the first one found; a miss has t < 0
// and triangle BVH_NO_HIT, as in bvh_traverse.glsl.
RayHit rqTrace(vec3 origin, vec3 dir, float tMin, float tMax, bool anyHit) {
  rayQueryEXT q;
  uint flags = gl_RayFlagsOpaqueEXT | (anyHit ? gl_RayFlagsTerminateOnFirstHitEXT : 0u);
  rayQueryInitializeEXT(q, rqScene, flags, 0xffu, origin, tMin, dir, tMax);
  while (rayQueryProceedEXT(q)) {
  }
  RayHit hit = RayHit(-1.0f, BVH_NO_HIT, 0u, 0u);
  if (rayQueryGetIntersectionTypeEXT(q, true) == gl_RayQueryCommittedIntersectionTriangleEXT) {
    hit.t = rayQueryGetIntersectionTEXT(q, true);
    uint first = rqTriangleIds[rayQueryGetIntersectionInstanceIdEXT(q, true)];
    hit.triangle = rqTriangleIds[first + uint(rayQueryGetIntersectionPrimitiveIndexEXT(q, true))];
  }
  return hit;
}

#ifndef RQ_NO_COUNTERS
// Adds this invocation's rays to the 64-bit ray counter (low, high words), one atomic per subgroup;
// the add that wraps the low word carries one into the high word.
void rqAddRays(uint rays) {
  uint total = subgroupAdd(rays);
  if (subgroupElect() && total != 0u) {
    uint old = atomicAdd(rqCounters[BVH_COUNTER_RAYS], total);
    if (old > 0xffffffffu - total) atomicAdd(rqCounters[BVH_COUNTER_RAYS + 1u], 1u);
  }
}
#endif  // RQ_NO_COUNTERS
