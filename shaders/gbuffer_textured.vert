#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/raster.h"
// Camera pass of a mesh with a texture (colour, cut-out or both): gbuffer.vert's attributes and the
// texture coordinate.
layout(push_constant) uniform PushBlock { CutoutDrawPush push; };
#include "gbuffer_vertex.glsl"
layout(location = 4) in vec2 inUv;
layout(location = 4) out vec2 uv;
void main() {
  gbufferVertex();
  uv = inUv;
}
