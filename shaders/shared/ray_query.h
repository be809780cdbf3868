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

// SceneAccelerationStructures::triangleIds(), in uints: the addresses of the scene's cut-outs (the
// CutoutTriangles', then the alpha words', each as (low, high)), then two per instance (where its
// triangles' ids start; for a cut-out mesh 1 + the CutoutTriangle of its triangle 0 minus that
// triangle's id, wrapping), then each instance's scene-order triangle ids in build order.
#define RQ_IDS_CUTOUTS 0
#define RQ_IDS_CUTOUT_WORDS 2
#define RQ_IDS_INSTANCES 4

PN_END
#endif
