// The ray-query tracer's kernels (rq_trace.comp, rq_rays.comp; linespace_trace_rq.comp for moving
// meshes): the driver-built top-level acceleration structure, the triangle ids of its hits, and
// the BVH tracer's counter layout (shared/bvh.h), of which they fill only the rays.
#ifndef PENUMBRA_SHARED_RAY_QUERY_H
#define PENUMBRA_SHARED_RAY_QUERY_H
#include "shared/bvh.h"
PN_BEGIN

// A kernel that traces the structures beside its own (linespace_trace.comp) defines the bindings
// first to move them, and RQ_NO_COUNTERS when it counts rays itself.
#ifndef RQ_BINDING_SCENE
#define RQ_BINDING_SCENE 0           // accelerationStructureEXT: the top level
#endif
#ifndef RQ_BINDING_TRIANGLE_IDS
#define RQ_BINDING_TRIANGLE_IDS 1  // SceneAccelerationStructures::triangleIds(): scene-order ids of the build order
#endif
#define RQ_BINDING_COUNTERS BVH_BINDING_COUNTERS

PN_END
#endif
