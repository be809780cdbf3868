// Thin-triangle conservative raster (Lauterbach et al. 2009, section 3.1): the push constants and
// varyings of thin_triangles.{vert,geom,frag} and the thinness test, one source for the shaders
// and the C++ side (tests and statistics apply the criterion the geometry shader applies).
#ifndef PENUMBRA_SHARED_THIN_H
#define PENUMBRA_SHARED_THIN_H
#include "shared/glsl_cpp.h"
PN_BEGIN

// Extra outward margin, in texels, over the exact half-texel box: absorbs the rasterizer's vertex
// snapping (1/256 texel on lavapipe) and float rounding, so "touches" never loses a texel to a tie.
#define THIN_EPSILON_TEXELS (1.0f / 64.0f)

// Edges of the near-clipped triangle (at most a quad) the fragment shader tests against.
#define THIN_EDGES 4

struct ThinTrianglePush {  // 80 bytes
  mat4 viewProj;           // the face's light view-projection (ShadowMapInfo::viewProj[face])
  float resolution;        // texels per side of the face
  float maxWidthTexels;    // thin: the smallest texel-space altitude is below this ...
  float minAspect;         // ... and longest edge / smallest altitude is at least this
  float texelWorld;        // ShadowMapInfo::texelWorld: world size of a texel at clip w = 1
};

// The criterion on a triangle's longest edge and twice its area, in texel units: the smallest
// altitude (2 * area / longest edge) is below maxWidthTexels and the aspect ratio (longest edge /
// that altitude) is at least minAspect, so small but regular triangles (dense scans) stay
// ordinary. A triangle collapsed to a segment (seen edge-on) has altitude 0 and is thin; one
// collapsed to a point is not (it has no extent to miss).
PN_FN bool thinMeasure(float longestEdge, float twiceArea, float maxWidthTexels, float minAspect) {
  if (!(longestEdge > 0.0f)) return false;
  float width = twiceArea / longestEdge;
  return width < maxWidthTexels && longestEdge >= minAspect * width;
}

// The criterion for a triangle with texel-space corners a, b, c.
PN_FN bool thinTriangle(vec2 a, vec2 b, vec2 c, float maxWidthTexels, float minAspect) {
  vec2 e0 = b - a;
  vec2 e1 = c - b;
  vec2 e2 = a - c;
  float longest = sqrt(max(dot(e0, e0), max(dot(e1, e1), dot(e2, e2))));
  return thinMeasure(longest, abs(e0.x * e2.y - e0.y * e2.x), maxWidthTexels, minAspect);
}

PN_END
#endif
