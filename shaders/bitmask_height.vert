#version 450
// Bitmask visibility sampling on a height-field receiver: the receiver mesh drawn orthographically
// onto its plane's map, each fragment carrying the surface's height over the plane.
#extension GL_GOOGLE_include_directive : require
#include "shared/bitmask.h"
layout(location = 0) in vec3 inPosition;
layout(location = 0) out float outHeight;
layout(std430, binding = BITMASK_DRAW_BINDING_FRAME) readonly buffer Frame { BitmaskFrame frame; };
void main() {
  outHeight = dot(frame.plane.xyz, inPosition) + frame.plane.w;
  gl_Position = vec4(receiverUv(frame, inPosition) * 2.0 - 1.0, 0.5, 1.0);
}
