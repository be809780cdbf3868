#version 450
// Arbitrary closest-hit rays (CandidateTracer::traceRays): RayQuery in, RayHit out (pad0 the packed
// shading normal turned towards the ray's origin, pad1 CS_HIT_* flags; shared/candidates.h).
// Mode by push constant: BVH with line-space nodes, the same BVH exact, or one line space alone.
// Bindings: BVH_BINDING_COUNTERS (2) counters, 3 queries, 4 hits, CS_BINDING_* (5..10).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#include "shared/bvh.h"
#include "shared/candidates.h"
layout(push_constant) uniform Push { CsRaysPush push; };
#define BVH_ADDRESSES push.bvh
#define CS_PARAMS push.cs
#include "bvh_ls_traverse.glsl"
layout(local_size_x = BVH_GROUP_SIZE) in;
layout(std430, binding = BVH_BINDING_QUERIES) readonly buffer Queries { RayQuery queries[]; };
layout(std430, binding = BVH_BINDING_HITS) writeonly buffer Hits { RayHit hits[]; };

void main() {
  uint rays = 0u;
  if (gl_GlobalInvocationID.x < push.count) {
    uint index = push.first + gl_GlobalInvocationID.x;
    RayQuery q = queries[index];
    RayHit hit = RayHit(-1.0f, BVH_NO_HIT, 0u, 0u);
    vec3 normal = vec3(0.0f, 0.0f, 1.0f);
    if (push.mode == CS_MODE_BOX) {
      float t;
      uint triangle;
      if (csHit(push.box, q.origin, q.direction, q.tMin, q.tMax, t, triangle, normal))
        hit = RayHit(t, triangle, 0u, CS_HIT_FROM_LINE_SPACE);
    } else {
      hit = bvhLsClosestHit(q.origin, q.direction, q.tMin, q.tMax, push.mode == CS_MODE_BVH_LS);
      vec3 face;  // the shading normal at the hit, interpolated (extrapolated on a candidate's plane) as csHit's
      if (hit.triangle != BVH_NO_HIT &&
          !csTriangleNormals(csSceneTriangles[hit.triangle], q.origin + hit.t * q.direction, normal, face)) {
        normal = face;
      }
    }
    if (hit.triangle != BVH_NO_HIT) {
      if (dot(normal, q.direction) > 0.0f) normal = -normal;
      hit.pad0 = packSnorm2x16(octahedralEncode(normal));
    }
    hits[index] = hit;
    rays = 1u;
  }
  bvhAddCounters(rays);
  uint tests = subgroupAdd(csCandidateTests);
  if (subgroupElect()) bvhAddCounter(CS_COUNTER_CANDIDATE_TESTS, tests);
}
