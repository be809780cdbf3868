#version 450
// Bitmask visibility sampling on a height-field receiver: the greatest height at each texel centre
// (the surface the light sees), by atomic max on the float's bits (heights are >= 0).
#extension GL_GOOGLE_include_directive : require
#include "shared/bitmask.h"
layout(location = 0) in float inHeight;
layout(std430, binding = BITMASK_DRAW_BINDING_FRAME) readonly buffer Frame { BitmaskFrame frame; };
layout(std430, binding = BITMASK_DRAW_BINDING_HEIGHTS) buffer Heights { uint heights[]; };
void main() {
  uint texel = uint(gl_FragCoord.y) * frame.resolution + uint(gl_FragCoord.x);
  atomicMax(heights[texel], floatBitsToUint(max(inHeight, 0.0)));
}
