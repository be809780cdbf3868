#version 450
// Shadow rays of the line-space tracer: one invocation per ShadingPoint of the TraceJob,
// dispatched indirectly from TraceCount. The same samples, ray origins and ray ends as
// bvh_trace.comp and EmbreeTracer::traceShadows; only the occlusion test differs (lsOccluded,
// an approximation that may only over-darken, apart from the skipped start node). Writes
// visibility[point.pixel] itself.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "shared/frame.h"
#include "shared/shading_point.h"
#include "shared/trace.h"
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

void main() {
  uint index = gl_GlobalInvocationID.x;
  uint rays = 0u;
  if (index < traceCount.count) {
    ShadingPoint point = points[index];
    GpuLight light = frame.light;
    // Like the reference: spp samples (0 means one), all aimed at the centre for point-like lights.
    uint n = max(point.spp, 1u);
    vec3 origin = point.position + point.normal * light.rayEpsilon;
    bool directional = light.type == LIGHT_DIRECTIONAL;
    uint visible = 0u;
    for (uint s = 0u; s < n; ++s) {
      vec3 q = lightSamplePoint(light, point.pixel, s, n);
      if (!lightReaches(light, point.position, point.normal, q)) continue;
      vec3 dir = directionToLight(light, point.position, q);
      float tMax = shadowRayEnd(distance(origin, q), directional, point.rayMax);
      ++rays;
      // The line space answers from where the ray is startOffset above the surface on (see LsPush).
      float tStart = min(lsPush.startOffset / max(dot(dir, point.normal), 1e-3), tMax);
      // The dynamic BVH is exact, so it takes the whole segment, as bvh_trace.comp does.
      if (lsOccluded(origin, dir, tStart, tMax)) continue;
      if (lsPush.dynamicRoot != BVH_NO_TREE &&
          bvhTraverse(lsPush.dynamicRoot, origin, dir, 0.0f, tMax, true).triangle != BVH_NO_HIT)
        continue;
      ++visible;
    }
    visibility[point.pixel] = float(visible) / float(n);
  }
  lsNodeVisits += bvhNodeVisits;  // the dynamic BVH's visits count as traversal steps too
  lsAddCounters(rays);
}
