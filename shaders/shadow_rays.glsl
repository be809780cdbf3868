// The shadow rays of one shading point, shared by every shadow-ray kernel (bvh_trace.comp,
// rq_trace.comp, linespace_trace.comp) so that all of them, and EmbreeTracer::traceShadows, trace
// the same samples from the same origins to the same ends: spp samples of the point's pixel (0
// means one), all aimed at the centre for point-like lights. Only the occlusion test differs:
// the includer defines shadowOccluded (not compiled on its own). Where the frame asks for it
// (FrameData::blockers, for the denoiser), the mean distance of the blockers found is written too.
#include "shared/frame.h"
#include "shared/shading_point.h"

layout(buffer_reference, std430, buffer_reference_align = 4) buffer BlockerDistances { float v[]; };

// Whether something blocks the segment origin + t * dir, t in [0, tMax] (dir is unit); blockerT:
// the distance of the blocker found (the first found, not necessarily the nearest), or -1 where
// the tracer does not know it.
bool shadowOccluded(ShadingPoint point, vec3 origin, vec3 dir, float tMax, out float blockerT);

// The fraction of the point's light samples that reach it; adds the rays traced to `rays`. With a
// blockers address (FrameData::blockers), writes there the mean distance of the blockers whose
// distance is known (0: none found).
float shadowVisibility(ShadingPoint point, GpuLight light, uvec2 blockers, inout uint rays) {
  uint n = max(point.spp, 1u);
  vec3 origin = shadowRayOrigin(light, point.position, point.normal);
  bool directional = light.type == LIGHT_DIRECTIONAL;
  uint visible = 0u, known = 0u;
  float blockerSum = 0.0f;
  for (uint s = 0u; s < n; ++s) {
    vec3 q = lightSamplePoint(light, point.pixel, s, n);
    if (!lightReaches(light, point.position, point.normal, q)) continue;
    vec3 dir = directionToLight(light, point.position, q);
    float tMax = shadowRayEnd(distance(origin, q), directional, point.rayMax);
    ++rays;
    float t;
    if (!shadowOccluded(point, origin, dir, tMax, t)) {
      ++visible;
    } else if (t >= 0.0f) {
      blockerSum += t;
      ++known;
    }
  }
  if (blockers != uvec2(0u)) BlockerDistances(blockers).v[point.pixel] = known > 0u ? blockerSum / float(known) : 0.0f;
  return float(visible) / float(n);
}
