#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#include "shared/thin.h"
// Thin-triangle pass: the geometry shader's rectangle holds the conservative region; keep the
// texels whose centre lies in it, i.e. within every edge slab and the grown bounding box, and
// write the least depth of the triangle's plane over the block of texels this one stands for
// (NDC depth is affine in texel coordinates over a plane), kept within its corners' depths: the
// mask is never farther than the triangle, and a long sliver sloping away from the light is not
// stamped with its nearest corner's depth all along.
layout(location = 0) flat in vec4 inEdges[THIN_EDGES];  // xy: unit normal, z/w: min/max of dot(normal, texel)
layout(location = THIN_EDGES) flat in vec4 inBox;       // xy: min, zw: max texel coordinates
layout(location = THIN_EDGES + 1) flat in vec4 inDepth;  // x: nearest corner, y: farthest, zw: gradient over texels
layout(location = THIN_EDGES + 2) flat in vec3 inDepthAt;  // xy: texel coordinates, z: the plane's depth there
layout(location = THIN_EDGES + 3) flat in uint inCutout;   // 1 + the CutoutTriangle whose alpha decides, or 0
layout(location = THIN_EDGES + 4) flat in vec3 inUvMap[3];
layout(push_constant) uniform PushBlock { ThinTrianglePush push; };
#include "thin_cutout.glsl"
void main() {
  vec2 p = gl_FragCoord.xy;
  if (p.x < inBox.x || p.y < inBox.y || p.x > inBox.z || p.y > inBox.w) discard;
  for (int i = 0; i < THIN_EDGES; ++i) {
    float d = dot(inEdges[i].xy, p);
    if (d < inEdges[i].z || d > inEdges[i].w) discard;
  }
  if (inCutout != 0u && thinCutoutUniform(inCutout - 1u, mat3(inUvMap[0], inUvMap[1], inUvMap[2]), p)) discard;
  // the plane's least depth over the block the texel stands for, within the corners' range
  vec2 g = inDepth.zw;
  float reach = 0.5 + THIN_DILATE_TEXELS + THIN_EPSILON_TEXELS;
  gl_FragDepth = clamp(inDepthAt.z + dot(g, p - inDepthAt.xy) - (abs(g.x) + abs(g.y)) * reach, inDepth.x, inDepth.y);
}
