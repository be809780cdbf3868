#version 450
// One level of the edge pyramid: each tile reduces the 2x2 tiles below it; level 1 finds the edge
// texels of the shadow map (3x3 depth edge, or a thin triangle within a texel: the thin mask is
// dilated, shared/thin.h) and their blocker depth, and the nearest depth of all its texels.
#extension GL_GOOGLE_include_directive : require
#include "shared/frame.h"
#include "shared/pyramid.h"
layout(local_size_x = PYRAMID_GROUP_SIZE, local_size_y = PYRAMID_GROUP_SIZE) in;
layout(binding = 0) uniform sampler2DArray shadowMap;
layout(binding = 1) uniform sampler2DArray thinMask;
layout(std430, binding = 2) buffer Pyramid { float tiles[]; };
layout(std430, binding = 3) readonly buffer ShadowTexels { float shadowTexels[]; };
layout(std430, binding = 4) readonly buffer ThinTexels { float thinTexels[]; };
layout(push_constant) uniform PushBlock { PyramidPush push; };
#include "light_texels.glsl"

float linearDepth(float z) { return linearShadowDepth(push.kind, push.nearPlane, push.farPlane, z); }

// Level 1: the nearest blocker depth of the edge texels among the 2x2 texels from q (1 = none), and
// the nearest depth of the 2x2 texels (the surface channel; 1 outside the face). A
// texel is an edge texel when its 3x3 neighbourhood (clamped to the face) spans more than the
// threshold; its blocker depth is the neighbourhood's minimum. The four neighbourhoods share one
// 4x4 window of loads (16 instead of 36).
vec2 edgeTile(ivec2 q, uint face) {
  int res = int(push.resolution);
  float raw[16], lin[16];
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      ivec2 r = clamp(q + ivec2(x - 1, y - 1), ivec2(0), ivec2(res - 1));
      raw[y * 4 + x] = LIGHT_TEXEL(shadowMap, shadowTexels, r, face, res);
      lin[y * 4 + x] = linearDepth(raw[y * 4 + x]);
    }
  }
  vec2 tile = vec2(1.0);
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      ivec2 c = q + ivec2(i, j);
      if (c.x >= res || c.y >= res) continue;  // outside: neutral for the minimum
      float s = lin[(j + 1) * 4 + i + 1];
      float nearest = raw[(j + 1) * 4 + i + 1];
      float delta = 0.0;
      for (int y = 0; y < 3; ++y) {
        for (int x = 0; x < 3; ++x) {
          delta = max(delta, abs(lin[(j + y) * 4 + i + x] - s));
          nearest = min(nearest, raw[(j + y) * 4 + i + x]);
        }
      }
      float blocker = delta > push.deltaThreshold ? nearest : 1.0;
      if (push.useThin != 0u) blocker = min(blocker, LIGHT_TEXEL(thinMask, thinTexels, c, face, res));
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

void main() {
  uint dim = pyramidDim(push.resolution, push.level);
  uvec3 id = gl_GlobalInvocationID;
  if (id.x >= dim || id.y >= dim || id.z >= push.faceCount) return;
  ivec2 q = 2 * ivec2(id.xy);
  vec2 nearest = push.level == 1u ? edgeTile(q, id.z) : min(min(below(q, id.z), below(q + ivec2(1, 0), id.z)), min(below(q + ivec2(0, 1), id.z), below(q + ivec2(1, 1), id.z)));
  uint tile = pyramidOffset(push.resolution, push.faceCount, push.level) + (id.z * dim + id.y) * dim + id.x;
  tiles[2u * tile + PYRAMID_EDGES] = nearest.x;
  tiles[2u * tile + PYRAMID_SURFACE] = nearest.y;
}
