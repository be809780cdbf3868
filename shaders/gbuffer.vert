#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/raster.h"
// Camera pass: world-space attributes for the G-buffer.
layout(push_constant) uniform PushBlock { GBufferPush push; };
#include "gbuffer_vertex.glsl"
void main() { gbufferVertex(); }
