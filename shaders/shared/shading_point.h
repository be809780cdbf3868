// A shading point as tracers consume it: one per covered pixel (or per PIP pixel), in tile order (shared/compact.h).
#ifndef PENUMBRA_SHARED_SHADING_POINT_H
#define PENUMBRA_SHARED_SHADING_POINT_H
#include "shared/glsl_cpp.h"
PN_BEGIN

// std430, 48 bytes: a vec3 followed by a scalar packs into one 16-byte slot on both sides.
struct ShadingPoint {
  vec3 position;  // world position
  uint pixel;     // y * width + x
  vec3 normal;    // unit, facing the camera
  uint spp;       // light samples to trace (1 for point-like lights)
  float rayMax;   // > 0: shadow rays stop this far from their origin (ray interval); 0: at the light
  uint pad0, pad1, pad2;
};

// Where a shadow ray towards light point q from surface point p ends (tfar), given the point's
// interval. Shared so that every tracer ends rays at exactly the same place.
PN_FN float shadowRayEnd(float distanceToLight, bool directional, float rayMax) {
  float end = directional ? 3.0e38f : distanceToLight * (1.0f - 1e-4f);
  return rayMax > 0.0f ? min(end, rayMax) : end;
}

PN_END
#endif
