#version 450
// Shadow rays of the BVH tracer: one invocation per ShadingPoint of the TraceJob, dispatched
// indirectly from TraceCount. Mirrors EmbreeTracer::traceShadows sample for sample, and writes
// visibility[point.pixel] itself (write-back fused into the trace).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "shared/frame.h"
#include "shared/shading_point.h"
#include "shared/trace.h"
#include "bvh_traverse.glsl"
layout(local_size_x = TRACE_GROUP_SIZE) in;
layout(std430, binding = 3) readonly buffer Points { ShadingPoint points[]; };
layout(std430, binding = 4) readonly buffer Count { TraceCount traceCount; };
layout(std430, binding = 5) readonly buffer Frame { FrameData frame; };
layout(std430, binding = 6) writeonly buffer Visibility { float visibility[]; };
layout(push_constant) uniform Push { BvhTracePush push; };

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
      if (!bvhAnyHit(origin, dir, 0.0f, tMax, push.dynamicRoot)) ++visible;
    }
    visibility[point.pixel] = float(visible) / float(n);
  }
  bvhAddCounters(rays);
}
