#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/raster.h"
// Light pass: depth only, one face of the shadow map per draw.
layout(location = 0) in vec3 inPosition;
layout(push_constant) uniform PushBlock { ShadowMapPush push; };
void main() { gl_Position = push.viewProj * vec4(inPosition, 1.0); }
