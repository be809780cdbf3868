// Inline ray queries against the scene's top-level acceleration structure
// (raytrace/acceleration_structures.h), included by rq_trace.comp, rq_rays.comp, indirect_rq.comp
// and linespace_trace_rq.comp. Culling is off. Opaque meshes are opaque geometry: the driver
// commits their hits itself. Cut-out meshes are not: their candidate hits come back to the proceed
// loop, which commits those where the texture is solid (cutout_test.glsl, as the BVH's traversal
// and the reference's filter decide). Includers enable GL_EXT_ray_query, GL_EXT_buffer_reference(_uvec2)
// and subgroup arithmetic.
#include "shared/ray_query.h"
#include "cutout_test.glsl"

layout(binding = RQ_BINDING_SCENE) uniform accelerationStructureEXT rqScene;
// The cut-outs' addresses, per instance where its ids start, then the scene-order id of each
// triangle in build order (shared/ray_query.h).
layout(std430, binding = RQ_BINDING_TRIANGLE_IDS) readonly buffer RqTriangleIds { uint rqTriangleIds[]; };
#ifndef RQ_NO_COUNTERS
layout(std430, binding = RQ_BINDING_COUNTERS) buffer RqCounters { uint rqCounters[BVH_COUNTER_WORDS]; };
#endif

// The scene-order id of primitive `primitive` of instance `instance`.
uint rqTriangleId(int instance, int primitive) {
  return rqTriangleIds[rqTriangleIds[RQ_IDS_INSTANCES + 2 * instance] + uint(primitive)];
}

// Whether the query's candidate, on a cut-out mesh, falls where its texture cuts it away.
bool rqCandidateCutAway(rayQueryEXT q) {
  int instance = rayQueryGetIntersectionInstanceIdEXT(q, false);
  uint id = rqTriangleId(instance, rayQueryGetIntersectionPrimitiveIndexEXT(q, false));
  uint cutout = id + rqTriangleIds[RQ_IDS_INSTANCES + 2 * instance + 1];
  uvec2 triangles = uvec2(rqTriangleIds[RQ_IDS_CUTOUTS], rqTriangleIds[RQ_IDS_CUTOUTS + 1]);
  uvec2 words = uvec2(rqTriangleIds[RQ_IDS_CUTOUT_WORDS], rqTriangleIds[RQ_IDS_CUTOUT_WORDS + 1]);
  return cutoutCutAway(triangles, words, cutout - 1u, rayQueryGetIntersectionBarycentricsEXT(q, false));
}

// The nearest hit within [tMin, tMax], or with anyHit the first one found; a miss has t < 0
// and triangle BVH_NO_HIT, as in bvh_traverse.glsl.
RayHit rqTrace(vec3 origin, vec3 dir, float tMin, float tMax, bool anyHit) {
  rayQueryEXT q;
  uint flags = anyHit ? gl_RayFlagsTerminateOnFirstHitEXT : 0u;
  rayQueryInitializeEXT(q, rqScene, flags, 0xffu, origin, tMin, dir, tMax);
  while (rayQueryProceedEXT(q)) {
    // only cut-out meshes' triangles are candidates (non-opaque geometry)
    if (!rqCandidateCutAway(q)) rayQueryConfirmIntersectionEXT(q);
  }
  RayHit hit = RayHit(-1.0f, BVH_NO_HIT, 0u, 0u);
  if (rayQueryGetIntersectionTypeEXT(q, true) == gl_RayQueryCommittedIntersectionTriangleEXT) {
    hit.t = rayQueryGetIntersectionTEXT(q, true);
    hit.triangle =
        rqTriangleId(rayQueryGetIntersectionInstanceIdEXT(q, true), rayQueryGetIntersectionPrimitiveIndexEXT(q, true));
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
