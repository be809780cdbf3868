#version 450
// Bitmask visibility sampling (Eisemann & Décoret 2007, section 4): each caster triangle's influence
// region on the receiver plane, the bounding box of its corners projected from the four corners
// of the light's square (a disk's bounding square), which holds every point whose view of the
// light the triangle can cut. The triangle is first clipped to the slab between the receiver
// plane and the light's lowest corner, each moved in by the caster margin: parts below the
// receiver or level with the light hide none of the light from it (and would project to infinity).
// Clipping leaves at most four triangles, each emitted as one rectangle with the clipped corners.
// Straight-line code and macros: lavapipe compiles loops over local arrays in a geometry shader
// very slowly.
#extension GL_GOOGLE_include_directive : require
#include "shared/bitmask.h"
layout(triangles) in;
layout(triangle_strip, max_vertices = 16) out;
layout(location = 0) in vec3 inWorld[];
layout(location = 0) flat out vec3 outA;
layout(location = 1) flat out vec3 outB;
layout(location = 2) flat out vec3 outC;
layout(std430, binding = BITMASK_DRAW_BINDING_FRAME) readonly buffer Frame { BitmaskFrame frame; };
// What was drawn: influence regions, and their texels in 64 bits (low word, carries): a large
// light over 285K triangles fills 1600 times a 512^2 map, which overflows 32 bits at 2048^2.
layout(std430, binding = BITMASK_DRAW_BINDING_FILL) buffer Fill { uint regions, texels, texelsHigh; } fill;

float height(vec3 x) { return dot(frame.plane.xyz, x) + frame.plane.w; }
float aboveReceiver(vec3 x) { return height(x) - frame.lightB.w; }
float belowLight(vec3 x) { return frame.lightT.w - frame.lightB.w - height(x); }

// x on the map, in [0, 1]^2 over its extent
vec2 onMap(vec3 x) {
  vec3 d = x - frame.origin.xyz;
  return vec2(dot(d, frame.axisU.xyz) / frame.axisU.w, dot(d, frame.axisV.xyz) / frame.axisV.w);
}

void emitRegion(vec3 a, vec3 b, vec3 c) {
  vec2 lo = vec2(1e30), hi = vec2(-1e30);
  for (int i = 0; i < 4; ++i) {
    vec3 corner = lightSquareCorner(frame, i);
    float hc = height(corner);
    // v seen from the corner, on the plane: 0 < height(v) < hc after clipping
    vec2 pa = onMap(corner + (a - corner) * (hc / (hc - height(a))));
    vec2 pb = onMap(corner + (b - corner) * (hc / (hc - height(b))));
    vec2 pc = onMap(corner + (c - corner) * (hc / (hc - height(c))));
    lo = min(lo, min(pa, min(pb, pc)));
    hi = max(hi, max(pa, max(pb, pc)));
    if (frame.field.x != 0.0) {
      // A height field: v shadows surface points from the plane up to its own height (or the
      // field's top); a shadow point moves along a straight line with the height, so the ends bound it.
      pa = onMap(corner + (a - corner) * ((hc - min(height(a), frame.field.y)) / (hc - height(a))));
      pb = onMap(corner + (b - corner) * ((hc - min(height(b), frame.field.y)) / (hc - height(b))));
      pc = onMap(corner + (c - corner) * ((hc - min(height(c), frame.field.y)) / (hc - height(c))));
      lo = min(lo, min(pa, min(pb, pc)));
      hi = max(hi, max(pa, max(pb, pc)));
    }
  }
  lo = max(lo, vec2(0.0));
  hi = min(hi, vec2(1.0));
  if (any(greaterThan(lo, hi))) return;
  vec2 size = (hi - lo) * float(frame.resolution);
  atomicAdd(fill.regions, 1u);
  uint texels = uint(min(size.x * size.y, 4e9));  // about the fragments it makes
  if (atomicAdd(fill.texels, texels) > ~texels) atomicAdd(fill.texelsHigh, 1u);  // the low word wrapped
  lo = lo * 2.0 - 1.0;
  hi = hi * 2.0 - 1.0;
  for (int k = 0; k < 4; ++k) {
    outA = a;
    outB = b;
    outC = c;
    gl_Position = vec4((k & 1) != 0 ? hi.x : lo.x, (k & 2) != 0 ? hi.y : lo.y, 0.0, 1.0);
    EmitVertex();
  }
  EndPrimitive();
}

// Clips triangle (a, b, c) to DIST(x) > 0 and hands each resulting triangle (one, or two for a
// quad) to EMIT. The odd corner (the one inside when one is, outside when two are) goes first.
#define CLIP(DIST, EMIT, a, b, c)                                                     \
  {                                                                                   \
    float da = DIST(a), db = DIST(b), dc = DIST(c);                                   \
    uint inside = uint(da > 0.0) + uint(db > 0.0) + uint(dc > 0.0);                   \
    if (inside == 3u) {                                                               \
      EMIT(a, b, c);                                                                  \
    } else if (inside != 0u) {                                                        \
      bool one = inside == 1u;                                                        \
      vec3 p = a, q = b, r = c;                                                       \
      float dp = da, dq = db, dr = dc;                                                \
      if ((db > 0.0) == one) {                                                        \
        p = b; q = c; r = a; dp = db; dq = dc; dr = da;                               \
      } else if ((dc > 0.0) == one) {                                                 \
        p = c; q = a; r = b; dp = dc; dq = da; dr = db;                               \
      }                                                                               \
      vec3 pq = mix(p, q, dp / (dp - dq)), pr = mix(p, r, dp / (dp - dr));            \
      if (one) {                                                                      \
        EMIT(p, pq, pr);                                                              \
      } else {                                                                        \
        EMIT(pq, q, r);                                                               \
        EMIT(pq, r, pr);                                                              \
      }                                                                               \
    }                                                                                 \
  }

void clipToLight(vec3 a, vec3 b, vec3 c) CLIP(belowLight, emitRegion, a, b, c)

// Watertight casters (--bitmask-watertight): a closed surface's shadow is that of its back faces,
// so a triangle facing all four of the light's corners is dropped (about half of the fill).
bool facesTheWholeLight(vec3 a, vec3 b, vec3 c) {
  vec3 n = cross(b - a, c - a);  // outward: counter-clockwise seen from outside
  for (int i = 0; i < 4; ++i) {
    if (!(dot(n, lightSquareCorner(frame, i) - a) > 0.0)) return false;
  }
  return true;
}

void main() {
  if (frame.onPlane.w != 0.0 && facesTheWholeLight(inWorld[0], inWorld[1], inWorld[2])) return;
  CLIP(aboveReceiver, clipToLight, inWorld[0], inWorld[1], inWorld[2])
}
