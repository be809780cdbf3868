// A shading point as tracers consume it: one per covered pixel (or per PIP pixel), in pixel order.
#ifndef PENUMBRA_SHARED_SHADING_POINT_H
#define PENUMBRA_SHARED_SHADING_POINT_H
#include "shared/glsl_cpp.h"
PN_BEGIN

// std430, 32 bytes: a vec3 followed by a uint packs into one 16-byte slot on both sides.
struct ShadingPoint {
  vec3 position;  // world position
  uint pixel;     // y * width + x
  vec3 normal;    // unit, facing the camera
  uint spp;       // light samples to trace (1 for point-like lights)
};

PN_END
#endif
