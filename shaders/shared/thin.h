// Thin-triangle conservative raster (Lauterbach et al. 2009, section 3.1): the push constants and
// varyings of thin_triangles.{vert,geom,frag} and the thinness test, one source for the shaders
// and the C++ side (tests and statistics apply the criterion the geometry shader applies).
#ifndef PENUMBRA_SHARED_THIN_H
#define PENUMBRA_SHARED_THIN_H
#include "shared/glsl_cpp.h"
PN_BEGIN

// thin_select.comp's bindings (raster/thin_triangle_pass.cpp).
#define THIN_SELECT_BINDING_VERTICES 0  // SceneGeometry::vertices(): RasterVertex, 9 floats
#define THIN_SELECT_BINDING_INDICES 1   // SceneGeometry::indices()
#define THIN_SELECT_BINDING_DRAWS 2     // the indirect draws' commands, written
#define THIN_SELECT_BINDING_LIST 3      // the selected triangles, written

// Extra outward margin, in texels, over the exact half-texel box: absorbs the rasterizer's vertex
// snapping (1/256 texel on lavapipe) and float rounding, so "touches" never loses a texel to a tie.
#define THIN_EPSILON_TEXELS (1.0f / 64.0f)

// The mask is dilated: texel t holds the nearest depth of the thin triangles touching any texel of
// the (2 * THIN_DILATE_TEXELS + 1)^2 block centred on t, so PIP classification reads one texel for
// its 3x3 neighbourhood instead of nine.
#define THIN_DILATE_TEXELS 1.0f

// Edges of the near-clipped triangle (at most a quad) the fragment shader tests against.
#define THIN_EDGES 4

struct ThinTrianglePush {  // 112 bytes
  mat4 viewProj;           // the face's light view-projection (ShadowMapInfo::viewProj[face])
  float resolution;        // texels per side of the face
  float maxWidthTexels;    // thin: the smallest texel-space altitude is below this ...
  float minAspect;         // ... and longest edge / smallest altitude is at least this
  float texelWorld;        // ShadowMapInfo::texelWorld: world size of a texel at clip w = 1
  // 1: the draw is of a cut-out mesh, each triangle kept whatever its shape wherever its alpha
  // changes (thin_cutout.glsl); its first triangle is CutoutTriangle `firstCutout` at `cutoutTriangles`
  uint cutouts;
  uint firstCutout;
  uvec2 cutoutTriangles;   // (low, high) addresses of the CutoutTriangles ...
  uvec2 cutoutTexels;      // ... and of the alpha words (shared/alpha.h)
  uint pad0, pad1;
};

// Selection (thin_select.comp): per light face, the thin triangles' indices are appended to a list
// drawn by two indexed indirect draws: the list, and (when the list overflowed) the whole scene.
#define THIN_SELECT_GROUP_SIZE 256
#define THIN_DRAW_WORDS 16  // uints per face in the draws buffer:
#define THIN_DRAW_LIST 0    //   VkDrawIndexedIndirectCommand over the face's part of the list
#define THIN_DRAW_ALL 5     //   VkDrawIndexedIndirectCommand over the scene (indexCount 0 unless overflowed)
#define THIN_DRAW_COUNT 10  //   thin triangles found (may exceed the capacity)

struct ThinSelectPush {  // 128 bytes
  ThinTrianglePush thin;
  uint face;             // draws[face * THIN_DRAW_WORDS ...], list[face * capacity * 3 ...]
  uint capacity;         // triangles per face in the list
  uint triangles;        // in the scene
  uint rowInvocations;   // invocations per row of the 2D dispatch grid
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
