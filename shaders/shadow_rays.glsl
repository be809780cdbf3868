// The shadow rays of one shading point, shared by every shadow-ray kernel (bvh_trace.comp,
// rq_trace.comp, linespace_trace.comp) so that all of them, and EmbreeTracer::traceShadows, trace
// the same samples from the same origins to the same ends: spp samples of the point's pixel (0
// means one), all aimed at the centre for point-like lights. Only the occlusion test differs:
// the includer defines shadowOccluded (not compiled on its own).
#include "shared/frame.h"
#include "shared/shading_point.h"

// Whether something blocks the segment origin + t * dir, t in [0, tMax] (dir is unit).
bool shadowOccluded(ShadingPoint point, vec3 origin, vec3 dir, float tMax);

// The fraction of the point's light samples that reach it; adds the rays traced to `rays`.
float shadowVisibility(ShadingPoint point, GpuLight light, inout uint rays) {
  uint n = max(point.spp, 1u);
  vec3 origin = shadowRayOrigin(light, point.position, point.normal);
  bool directional = light.type == LIGHT_DIRECTIONAL;
  uint visible = 0u;
  for (uint s = 0u; s < n; ++s) {
    vec3 q = lightSamplePoint(light, point.pixel, s, n);
    if (!lightReaches(light, point.position, point.normal, q)) continue;
    vec3 dir = directionToLight(light, point.position, q);
    float tMax = shadowRayEnd(distance(origin, q), directional, point.rayMax);
    ++rays;
    if (!shadowOccluded(point, origin, dir, tMax)) ++visible;
  }
  return float(visible) / float(n);
}
