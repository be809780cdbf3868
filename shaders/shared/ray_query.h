// The ray-query tracer's kernels (rq_trace.comp, rq_rays.comp): the driver-built top-level
// acceleration structure, the per-instance first triangle ids, and the BVH tracer's counter layout
// (shared/bvh.h), of which they fill only the rays.
#ifndef PENUMBRA_SHARED_RAY_QUERY_H
#define PENUMBRA_SHARED_RAY_QUERY_H
#include "shared/bvh.h"
PN_BEGIN

#define RQ_BINDING_SCENE 0           // accelerationStructureEXT: the top level
#define RQ_BINDING_FIRST_TRIANGLE 1  // uint per instance: scene-order id of its mesh's first triangle
#define RQ_BINDING_COUNTERS BVH_BINDING_COUNTERS

PN_END
#endif
