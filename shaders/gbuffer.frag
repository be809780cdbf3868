#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/raster.h"
layout(push_constant) uniform PushBlock { GBufferPush push; };
#include "gbuffer_fragment.glsl"
void main() { gbufferFragment(vec3(1.0)); }
