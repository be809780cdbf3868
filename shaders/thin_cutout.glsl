// Thin-triangle pass over a cut-out mesh (ThinTrianglePush.cutouts): a triangle that is not thin
// still hides holes or strands finer than a texel wherever its texture's alpha changes, but where
// its alpha is the same over a texel's block it is as the shadow map draws it (all solid: an
// opaque plane, whose edges the depth-edge test finds; all cut away: nothing). So the mask keeps a
// texel only where the alpha over the part of the triangle in the texel's block is mixed: the
// geometry shader passes the projective map from texel coordinates to texture coordinates over
// the triangle's plane, the fragment shader bounds the block's texture coordinates with it and asks
// the texture's alpha ranges (shared/alpha.h) whether one rule holds over them. The includer
// declares `push` (ThinTrianglePush) and enables GL_EXT_buffer_reference and _uvec2.
#ifndef PENUMBRA_THIN_CUTOUT_GLSL
#define PENUMBRA_THIN_CUTOUT_GLSL
#include "cutout_test.glsl"

CutoutTriangle thinCutoutTriangle(uint index) { return CutoutTriangleArray(push.cutoutTriangles).v[index]; }

// The map m of triangle t (clip-space corners c0..c2, all in front of the light) from texel
// coordinates to texture coordinates over its plane: m * (x, y, 1) = (u s, v s, s), where s is 1 over
// the plane point's clip w (> 0 in front). False when the corners give no such map.
bool thinUvMap(vec4 c0, vec4 c1, vec4 c2, CutoutTriangle t, out mat3 m) {
  mat3 corners = mat3(c0.xyw, c1.xyw, c2.xyw);  // scaled barycentrics -> (ndc x, ndc y, 1)
  mat3 toNdc = mat3(vec3(2.0 / push.resolution, 0.0, 0.0), vec3(0.0, 2.0 / push.resolution, 0.0), vec3(-1.0, -1.0, 1.0));
  mat3 uvs = mat3(vec3(t.uv0, 1.0), vec3(t.uv1, 1.0), vec3(t.uv2, 1.0));
  m = uvs * inverse(corners) * toNdc;
  for (int i = 0; i < 3; ++i) {
    if (any(isnan(m[i])) || any(isinf(m[i]))) return false;
  }
  return abs(determinant(corners)) > 0.0;
}

// The (least, greatest) alpha of cell (x, y) of level `level` of t's texture (shared/alpha.h),
// whose first cell is half word `first` (level 0: the texels).
uvec2 thinAlphaCell(CutoutTriangle t, uint level, uint first, uint x, uint y) {
  if (level == 0u) {
    uint texel = t.texels + y * t.width + x;
    return uvec2(cutoutAlpha(CutoutWordArray(push.cutoutTexels).v[texel >> 2], texel));
  }
  uint cellAt = first + y * cutoutLevelSize(t.width, level) + x;
  return cutoutRange(CutoutWordArray(push.cutoutTexels).v[cellAt >> 1], cellAt);
}

// The texels [lo, hi] along one side of `size` texels, wrapped: one interval (xy, with zw empty),
// two (xy up to the last texel, zw from the first) or every texel.
ivec4 thinTexelSpans(int lo, int hi, int size) {
  if (hi - lo + 1 >= size) return ivec4(0, size - 1, 0, -1);
  int a = lo - size * int(floor(float(lo) / float(size)));
  int b = a + (hi - lo);
  return b < size ? ivec4(a, b, 0, -1) : ivec4(a, size - 1, 0, b - size);
}

// The cells of `level` over spans s (thinTexelSpans): how many.
int thinCellCount(ivec4 s, uint level) {
  return (s.y >> level) - (s.x >> level) + 1 + (s.w >= 0 ? (s.w >> level) - (s.z >> level) + 1 : 0);
}

// Cell k of them.
uint thinCell(ivec4 s, uint level, int k) {
  int first = (s.y >> level) - (s.x >> level) + 1;
  return uint(k < first ? (s.x >> level) + k : (s.z >> level) + k - first);
}

// Whether triangle `index` (map m) is all solid or all cut away over the block of texel p.
bool thinCutoutUniform(uint index, mat3 m, vec2 p) {
  CutoutTriangle t = thinCutoutTriangle(index);
  float reach = 0.5 + THIN_DILATE_TEXELS + THIN_EPSILON_TEXELS;
  vec3 h0 = m * vec3(p + vec2(-reach, -reach), 1.0);
  vec3 h1 = m * vec3(p + vec2(reach, -reach), 1.0);
  vec3 h2 = m * vec3(p + vec2(-reach, reach), 1.0);
  vec3 h3 = m * vec3(p + vec2(reach, reach), 1.0);
  if (!(min(min(h0.z, h1.z), min(h2.z, h3.z)) > 0.0)) return false;  // the block reaches the plane's horizon
  vec2 a0 = h0.xy / h0.z, a1 = h1.xy / h1.z, a2 = h2.xy / h2.z, a3 = h3.xy / h3.z;
  // the triangle's part in the block lies in both boxes
  vec2 lo = max(min(min(a0, a1), min(a2, a3)), min(t.uv0, min(t.uv1, t.uv2)));
  vec2 hi = min(max(max(a0, a1), max(a2, a3)), max(t.uv0, max(t.uv1, t.uv2)));
  vec2 size = vec2(t.width, t.height);
  // the texels' indices (shared/alpha.h takes the one the point lies in), the box a hundredth of a
  // texel wider for rounding
  vec2 first = floor(lo * size - 0.01), last = floor(hi * size + 0.01);
  if (any(greaterThan(first, last)) || max(max(abs(first.x), abs(first.y)), max(abs(last.x), abs(last.y))) > 1.0e6) {
    return false;
  }
  ivec4 xs = thinTexelSpans(int(first.x), int(last.x), int(t.width));
  ivec4 ys = thinTexelSpans(int(first.y), int(last.y), int(t.height));
  // the finest level at which at most 4 x 4 cells cover them (one at the last level)
  uint level = 0u;
  while (thinCellCount(xs, level) > 4 || thinCellCount(ys, level) > 4) ++level;
  int nx = thinCellCount(xs, level), ny = thinCellCount(ys, level);
  uint levelAt = t.ranges;  // the level's first cell, past the finer levels
  for (uint l = 1u; l < level; ++l) levelAt += cutoutLevelSize(t.width, l) * cutoutLevelSize(t.height, l);
  uvec2 range = uvec2(255u, 0u);
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      uvec2 cell = thinAlphaCell(t, level, levelAt, thinCell(xs, level, i), thinCell(ys, level, j));
      range = uvec2(min(range.x, cell.x), max(range.y, cell.y));
    }
  }
  return cutoutSolid(range.x, t.factor, t.cutoff) == cutoutSolid(range.y, t.factor, t.cutoff);
}

#endif  // PENUMBRA_THIN_CUTOUT_GLSL
