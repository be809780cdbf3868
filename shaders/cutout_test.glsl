// Cut-outs read through device addresses (core/cutouts.h's CutoutData uploaded): the record and
// alpha-word arrays, and shared/alpha.h's rule at a hit's barycentrics, one test for the BVH's
// traversal (bvh_traverse.glsl) and the ray queries' candidate loop (rq_common.glsl). Includers
// enable GL_EXT_buffer_reference and GL_EXT_buffer_reference_uvec2.
#ifndef PENUMBRA_CUTOUT_TEST_GLSL
#define PENUMBRA_CUTOUT_TEST_GLSL
#include "shared/alpha.h"

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer CutoutTriangleArray { CutoutTriangle v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer CutoutWordArray { uint v[]; };

// Whether a hit at barycentrics `bary` on CutoutTriangle `index` of the array at `triangles` falls
// where its texture (alpha words at `words`) cuts it away.
bool cutoutCutAway(uvec2 triangles, uvec2 words, uint index, vec2 bary) {
  CutoutTriangle c = CutoutTriangleArray(triangles).v[index];
  uint texel = c.texels + cutoutTexel(cutoutUv(c.uv0, c.uv1, c.uv2, bary.x, bary.y), c.width, c.height);
  return !cutoutSolid(cutoutAlpha(CutoutWordArray(words).v[texel >> 2], texel), c.factor, c.cutoff);
}

#endif  // PENUMBRA_CUTOUT_TEST_GLSL
