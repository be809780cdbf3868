#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#include "shared/raster.h"
// Camera pass of a cut-out mesh: gbuffer.frag where the texture keeps the surface, nothing where
// it cuts it away (the derivatives are taken before the discard, by every lane of the quad).
layout(push_constant) uniform PushBlock { CutoutDrawPush push; };
#include "cutout_draw.glsl"
#include "gbuffer_fragment.glsl"
layout(location = 4) in vec2 uv;
void main() {
  gbufferFragment();
  if (cutAway(uv)) discard;
}
