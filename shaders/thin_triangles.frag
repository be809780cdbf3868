#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/thin.h"
// Thin-triangle pass: the geometry shader's rectangle holds the conservative region; keep the
// texels whose centre lies in it, i.e. within every edge slab and the grown bounding box, and
// write one flat depth, the nearest corner's, so the mask is never farther than the triangle.
layout(location = 0) flat in vec4 inEdges[THIN_EDGES];  // xy: unit normal, z/w: min/max of dot(normal, texel)
layout(location = THIN_EDGES) flat in vec4 inBox;       // xy: min, zw: max texel coordinates
layout(location = THIN_EDGES + 1) flat in float inDepth;
void main() {
  vec2 p = gl_FragCoord.xy;
  if (p.x < inBox.x || p.y < inBox.y || p.x > inBox.z || p.y > inBox.w) discard;
  for (int i = 0; i < THIN_EDGES; ++i) {
    float d = dot(inEdges[i].xy, p);
    if (d < inEdges[i].z || d > inEdges[i].w) discard;
  }
  gl_FragDepth = inDepth;
}
