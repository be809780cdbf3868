#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#include "shared/raster.h"
// Light pass of a cut-out mesh: no depth where its texture cuts it away.
layout(push_constant) uniform PushBlock { CutoutDrawPush push; };
#include "cutout_draw.glsl"
layout(location = 0) in vec2 uv;
void main() {
  if (cutAway(uv)) discard;
}
