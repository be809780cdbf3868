#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/raster.h"
// Light pass of a cut-out mesh: shadow_map.vert and the texture coordinate.
layout(location = 0) in vec3 inPosition;
layout(location = 4) in vec2 inUv;
layout(push_constant) uniform PushBlock { CutoutDrawPush push; };
layout(location = 0) out vec2 uv;
void main() {
  gl_Position = push.viewProj * vec4(inPosition, 1.0);
  uv = inUv;
}
