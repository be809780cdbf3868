#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#include "shared/raster.h"
// Camera pass of a cut-out mesh: gbuffer_textured.frag where the texture keeps the surface, nothing
// where it cuts it away (the derivatives and the colour are taken before the discard, by every lane
// of the quad).
layout(push_constant) uniform PushBlock { CutoutDrawPush push; };
#include "cutout_draw.glsl"
#include "gbuffer_fragment.glsl"
layout(location = 4) in vec2 uv;
layout(binding = GBUFFER_BINDING_COLOR) uniform sampler2D colorTexture;
void main() {
  gbufferFragment(texture(colorTexture, uv).rgb);
  if (cutAway(uv)) discard;
}
