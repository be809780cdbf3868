#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/raster.h"
// Camera pass of an opaque mesh with a colour texture: gbuffer.frag, its base colour times the texture's.
layout(push_constant) uniform PushBlock { CutoutDrawPush push; };
#include "gbuffer_fragment.glsl"
layout(location = 4) in vec2 uv;
layout(binding = GBUFFER_BINDING_COLOR) uniform sampler2D colorTexture;
void main() { gbufferFragment(texture(colorTexture, uv).rgb); }
