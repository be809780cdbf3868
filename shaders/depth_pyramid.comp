#version 450
// One level of the edge pyramid: each tile reduces the 2x2 tiles below it; level 1 finds the edge
// texels of the shadow map (3x3 depth edge, or a thin triangle within a texel: the thin mask is
// dilated, shared/thin.h) and their blocker depth.
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

// The blocker depth of texel q if it is an edge texel, else 1.
float edgeTexel(ivec2 q, uint face) {
  int res = int(push.resolution);
  if (q.x >= res || q.y >= res) return 1.0;  // outside: neutral for the minimum
  bool texelBuffer = push.texelBuffer != 0u;
  float depth = LIGHT_TEXEL(texelBuffer, shadowMap, shadowTexels, q, face, res);
  float s = linearDepth(depth);
  float nearest = depth;
  float delta = 0.0;
  for (int y = -1; y <= 1; ++y) {
    for (int x = -1; x <= 1; ++x) {
      ivec2 r = clamp(q + ivec2(x, y), ivec2(0), ivec2(res - 1));
      float other = LIGHT_TEXEL(texelBuffer, shadowMap, shadowTexels, r, face, res);
      delta = max(delta, abs(linearDepth(other) - s));
      nearest = min(nearest, other);
    }
  }
  float blocker = delta > push.deltaThreshold ? nearest : 1.0;
  if (push.useThin != 0u) blocker = min(blocker, LIGHT_TEXEL(texelBuffer, thinMask, thinTexels, q, face, res));
  return blocker;
}

float below(ivec2 q, uint face) {
  if (push.level == 1u) return edgeTexel(q, face);
  uint dim = pyramidDim(push.resolution, push.level - 1u);
  if (uint(q.x) >= dim || uint(q.y) >= dim) return 1.0;
  uint base = pyramidOffset(push.resolution, push.faceCount, push.level - 1u);
  return tiles[base + (face * dim + uint(q.y)) * dim + uint(q.x)];
}

void main() {
  uint dim = pyramidDim(push.resolution, push.level);
  uvec3 id = gl_GlobalInvocationID;
  if (id.x >= dim || id.y >= dim || id.z >= push.faceCount) return;
  ivec2 q = 2 * ivec2(id.xy);
  float nearest = min(min(below(q, id.z), below(q + ivec2(1, 0), id.z)), min(below(q + ivec2(0, 1), id.z), below(q + ivec2(1, 1), id.z)));
  tiles[pyramidOffset(push.resolution, push.faceCount, push.level) + (id.z * dim + id.y) * dim + id.x] = nearest;
}
