#version 450
// One level of the edge pyramid: each tile reduces the 2x2 tiles below it; level 1 finds the edge
// texels of the shadow map (the near side of a 3x3 depth edge, or a thin triangle on the texel) and
// their blocker depth, and the nearest depth of all its texels; from
// level 2 on each tile also gets its surface fit (shared/pyramid.h).
#extension GL_GOOGLE_include_directive : require
#include "shared/frame.h"
#include "shared/pyramid.h"
layout(local_size_x = PYRAMID_GROUP_SIZE, local_size_y = PYRAMID_GROUP_SIZE) in;
layout(binding = PYRAMID_BINDING_SHADOW_MAP) uniform sampler2DArray shadowMap;
layout(binding = PYRAMID_BINDING_THIN_MASK) uniform sampler2DArray thinMask;
layout(std430, binding = PYRAMID_BINDING_TILES) buffer Pyramid { float tiles[]; };
layout(std430, binding = PYRAMID_BINDING_SHADOW_TEXELS) readonly buffer ShadowTexels { float shadowTexels[]; };
layout(std430, binding = PYRAMID_BINDING_THIN_TEXELS) readonly buffer ThinTexels { float thinTexels[]; };
layout(push_constant) uniform PushBlock { PyramidPush push; };
#include "light_texels.glsl"

float linearDepth(float z) { return linearShadowDepth(push.kind, push.nearPlane, push.farPlane, z); }

// Level 1: the nearest blocker depth of the edge texels among the 2x2 texels from q (1 = none), and
// the nearest depth of the 2x2 texels (the surface channel; 1 outside the face). An edge texel is
// the near side of a depth edge: a texel of its 3x3 neighbourhood (clamped to the face) lies
// farther by more than the threshold, so the blocker's silhouette runs within a texel of it; its
// blocker depth is the neighbourhood's minimum (a blocker rising towards its silhouette). The far
// side holds no blocker of its own. A thin triangle's texel is an edge texel too, at the depth of
// the thin mask's 3x3 opening: the mask is dilated (each texel holds the nearest thin triangle
// within its 3x3 block), so the largest of its 3x3 values is no nearer than any thin triangle
// touching this texel, and the mask's search reaches as far from it as from an edge texel. The
// four neighbourhoods share one 4x4 window of loads of each map (16 instead of 36); the thin mask's
// is read only where one of the four holds a thin triangle (else every opening is 1).
vec2 edgeTile(ivec2 q, uint face) {
  int res = int(push.resolution);
  float raw[16], lin[16], thin[16];
  bool stamped = false;
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      ivec2 r = clamp(q + ivec2(x - 1, y - 1), ivec2(0), ivec2(res - 1));
      raw[y * 4 + x] = LIGHT_TEXEL(shadowMap, shadowTexels, r, face, res);
      lin[y * 4 + x] = linearDepth(raw[y * 4 + x]);
      bool centre = (x == 1 || x == 2) && (y == 1 || y == 2);
      thin[y * 4 + x] = push.useThin != 0u && centre ? LIGHT_TEXEL(thinMask, thinTexels, r, face, res) : 1.0;
      stamped = stamped || thin[y * 4 + x] < 1.0;
    }
  }
  for (int k = 0; stamped && k < 16; ++k) {  // the ring around the four, read above
    int x = k & 3, y = k >> 2;
    if ((x == 1 || x == 2) && (y == 1 || y == 2)) continue;
    thin[k] = LIGHT_TEXEL(thinMask, thinTexels, clamp(q + ivec2(x - 1, y - 1), ivec2(0), ivec2(res - 1)), face, res);
  }
  vec2 tile = vec2(1.0);
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      ivec2 c = q + ivec2(i, j);
      if (c.x >= res || c.y >= res) continue;  // outside: neutral for the minimum
      float s = lin[(j + 1) * 4 + i + 1];
      float nearest = raw[(j + 1) * 4 + i + 1];
      float farther = 0.0, opening = 0.0;
      for (int y = 0; y < 3; ++y) {
        for (int x = 0; x < 3; ++x) {
          farther = max(farther, lin[(j + y) * 4 + i + x] - s);
          nearest = min(nearest, raw[(j + y) * 4 + i + x]);
          opening = max(opening, thin[(j + y) * 4 + i + x]);
        }
      }
      float blocker = min(farther > push.deltaThreshold ? nearest : 1.0, opening);
      tile = min(tile, vec2(blocker, raw[(j + 1) * 4 + i + 1]));
    }
  }
  return tile;
}

vec2 below(ivec2 q, uint face) {
  uint dim = pyramidDim(push.resolution, push.level - 1u);
  if (uint(q.x) >= dim || uint(q.y) >= dim) return vec2(1.0);
  uint tile = pyramidOffset(push.resolution, push.faceCount, push.level - 1u) + (face * dim + uint(q.y)) * dim + uint(q.x);
  return vec2(tiles[2u * tile + PYRAMID_EDGES], tiles[2u * tile + PYRAMID_SURFACE]);
}

// A few float steps at raw depth 1, added to each level's `below` for the rounding of the fits.
const float kFitSlack = 4.8e-7;

// Level 2: the least-squares plane of the 4x4 texels from q and the deepest any lies below it.
vec4 texelFit(ivec2 q, uint face) {
  int res = int(push.resolution);
  float z[16], mean = 0.0;
  vec2 g = vec2(0.0);
  for (int j = 0; j < 16; ++j) {
    vec2 o = vec2(j & 3, j >> 2) - 1.5;  // from the tile's centre
    z[j] = LIGHT_TEXEL(shadowMap, shadowTexels, clamp(q + ivec2(j & 3, j >> 2), ivec2(0), ivec2(res - 1)), face, res);
    mean += z[j];
    g += o * z[j];
  }
  mean /= 16.0;
  g /= 20.0;  // sum of o.x^2 over the 16 texels
  float below = 0.0;
  for (int j = 0; j < 16; ++j) below = max(below, mean + dot(g, vec2(j & 3, j >> 2) - 1.5) - z[j]);
  return vec4(mean, g, below + kFitSlack);
}

// Level k >= 3: a plane through the four children's fits' centres, and the deepest any child's
// texels may lie below it (its own `below`, plus how far its plane dips under this one's over the
// span of its texel centres).
vec4 childrenFit(ivec2 q, uint face) {
  uint k = push.level, dim = pyramidDim(push.resolution, k - 1u);
  vec4 child[4];
  bool inside[4];
  for (int j = 0; j < 4; ++j) {
    ivec2 c = q + ivec2(j & 1, j >> 1);
    inside[j] = uint(c.x) < dim && uint(c.y) < dim;
    uint at = pyramidFitIndex(push.resolution, push.faceCount, push.levels, k - 1u,
                              (face * dim + uint(inside[j] ? c.y : q.y)) * dim + uint(inside[j] ? c.x : q.x));
    child[j] = vec4(tiles[at + PYRAMID_FIT_CENTRE], tiles[at + PYRAMID_FIT_GRADIENT],
                    tiles[at + PYRAMID_FIT_GRADIENT + 1u], tiles[at + PYRAMID_FIT_BELOW]);
  }
  float toChild = float(1u << (k - 2u));  // from this tile's centre to a child's
  float centre = 0.25 * (child[0].x + child[1].x + child[2].x + child[3].x);
  vec2 g = vec2(child[1].x + child[3].x - child[0].x - child[2].x, child[2].x + child[3].x - child[0].x - child[1].x) /
           (4.0 * toChild);
  float childSpan = 0.5 * float((1u << (k - 1u)) - 1u);  // a child's texel centres from its centre
  float below = 0.0;
  for (int j = 0; j < 4; ++j) {
    if (!inside[j]) continue;
    vec2 o = toChild * (2.0 * vec2(j & 1, j >> 1) - 1.0);
    vec2 dg = g - child[j].yz;
    below = max(below, centre + dot(g, o) - child[j].x + childSpan * (abs(dg.x) + abs(dg.y)) + child[j].w);
  }
  return vec4(centre, g, below + kFitSlack);
}

void main() {
  uint dim = pyramidDim(push.resolution, push.level);
  uvec3 id = gl_GlobalInvocationID;
  if (id.x >= dim || id.y >= dim || id.z >= push.faceCount) return;
  ivec2 q = 2 * ivec2(id.xy);
  vec2 nearest = push.level == 1u ? edgeTile(q, id.z) : min(min(below(q, id.z), below(q + ivec2(1, 0), id.z)), min(below(q + ivec2(0, 1), id.z), below(q + ivec2(1, 1), id.z)));
  uint tile = pyramidOffset(push.resolution, push.faceCount, push.level) + (id.z * dim + id.y) * dim + id.x;
  tiles[2u * tile + PYRAMID_EDGES] = nearest.x;
  tiles[2u * tile + PYRAMID_SURFACE] = nearest.y;
  if (push.level < 2u) return;
  vec4 fit = push.level == 2u ? texelFit(2 * q, id.z) : childrenFit(q, id.z);
  uint at = pyramidFitIndex(push.resolution, push.faceCount, push.levels, push.level, (id.z * dim + id.y) * dim + id.x);
  tiles[at + PYRAMID_FIT_CENTRE] = fit.x;
  tiles[at + PYRAMID_FIT_GRADIENT] = fit.y;
  tiles[at + PYRAMID_FIT_GRADIENT + 1u] = fit.z;
  tiles[at + PYRAMID_FIT_BELOW] = fit.w;
}
