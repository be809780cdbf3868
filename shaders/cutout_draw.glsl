// The alpha test of the cut-out draws (gbuffer_cutout.frag, shadow_map_cutout.frag): shared/alpha.h's
// rule at the texture coordinate the rasterizer interpolates. The includer declares the push
// constants `push` (CutoutDrawPush) and enables GL_EXT_buffer_reference and _uvec2.
#ifndef PENUMBRA_CUTOUT_DRAW_GLSL
#define PENUMBRA_CUTOUT_DRAW_GLSL
#include "cutout_test.glsl"

// Whether the mesh's texture cuts the surface away at `uv`.
bool cutAway(vec2 uv) {
  uint texel = push.first + cutoutTexel(uv, push.width, push.height);
  return !cutoutSolid(cutoutAlpha(CutoutWordArray(push.texels).v[texel >> 2], texel), push.factor, push.cutoff);
}

#endif  // PENUMBRA_CUTOUT_DRAW_GLSL
