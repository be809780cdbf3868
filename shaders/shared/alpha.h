// Alpha-tested cut-outs (Scene's Cutout): the one rule by which every method and the reference
// decide whether a point of a cut-out triangle is solid. The texture coordinate is interpolated with
// the hit's barycentrics, wrapped (glTF's default REPEAT) and looked up at the nearest texel of the
// full-resolution image; solid where factor * alpha >= cutoff (alpha in [0, 1] from 8 bits).
#ifndef PENUMBRA_SHARED_ALPHA_H
#define PENUMBRA_SHARED_ALPHA_H
#include "shared/glsl_cpp.h"
PN_BEGIN

// The texture coordinate at barycentrics (u, v) of a triangle with vertex coordinates t0, t1, t2
// (point = (1 - u - v) v0 + u v1 + v v2, Embree's and the BVH's convention).
PN_FN vec2 cutoutUv(vec2 t0, vec2 t1, vec2 t2, float u, float v) {
  return t0 * (1.0f - u - v) + t1 * u + t2 * v;
}

// The index (row-major, row 0 at v = 0) of the texel nearest to uv in a width x height image.
PN_FN uint cutoutTexel(vec2 uv, uint width, uint height) {
  float fx = uv.x - floor(uv.x);
  float fy = uv.y - floor(uv.y);
  uint x = min(uint(fx * float(width)), width - 1u);
  uint y = min(uint(fy * float(height)), height - 1u);
  return y * width + x;
}

// Whether a texel of 8-bit alpha `alpha8` is solid under the material's factor and cutoff.
PN_FN bool cutoutSolid(uint alpha8, float factor, float cutoff) {
  return factor * (float(alpha8) / 255.0f) >= cutoff;
}

// A triangle of a cut-out mesh as the tracers test it (core/cutouts.h), std430 48 bytes;
// BvhTriangle.cutout is 1 + its index. Its texture's alpha lies in a buffer of words, four texels
// to a word (the lowest byte first), from texel `texels` on; its alpha ranges (below) from half
// word `ranges` on.
struct CutoutTriangle {
  vec2 uv0;
  vec2 uv1;
  vec2 uv2;
  uint texels;
  uint width;
  uint height;
  float factor;
  float cutoff;
  uint ranges;
};

// The alpha of texel `texel` (its index among all the words' texels) from its word, texel / 4.
PN_FN uint cutoutAlpha(uint word, uint texel) {
  return (word >> (8u * (texel & 3u))) & 0xffu;
}

// Alpha ranges: a pyramid over each texture for the thin-triangle pass (thin_cutout.glsl), which
// asks whether a texture is all solid or all cut away over a box of texels. Level l >= 1 has
// cutoutLevelSize(width, l) x cutoutLevelSize(height, l) cells, row-major, cell (x, y) covering
// texels [x 2^l, (x + 1) 2^l) x [y 2^l, (y + 1) 2^l) of the image (clipped to it); levels follow one
// another up to the first of one cell; level 0 is the alpha itself. A cell is a half word, two to a
// word (the lower half first): its least alpha in the low byte, its greatest in the high byte.
PN_FN uint cutoutLevelSize(uint size, uint level) {
  return (size + (1u << level) - 1u) >> level;
}

// The (least, greatest) alpha of half word `cellAt` from its word, cellAt / 2.
PN_FN uvec2 cutoutRange(uint word, uint cellAt) {
  uint cell = (word >> (16u * (cellAt & 1u))) & 0xffffu;
  return uvec2(cell & 0xffu, cell >> 8u);
}

PN_END
#endif
