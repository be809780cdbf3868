#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#include "shared/thin.h"
// Thin-triangle pass (Lauterbach et al. 2009, section 3.1): keeps only the triangles that are thin
// in texel space and rasterizes them conservatively (Hasselgren et al. 2005), so every texel whose
// square the triangle touches gets a fragment. Ordinary triangles emit nothing. It is drawn over the
// triangles thin_select.comp picked (thinOnFace in thin_face.glsl, the same test).
//
// Enlargement: Hasselgren moves each edge outward by the half-texel box's support along its
// normal, 0.5 * (|nx| + |ny|), and keeps the result inside the bounding box grown by half a texel.
// Here each edge contributes a slab (between the edge and the farthest corner, both moved out by
// that support + THIN_EPSILON_TEXELS), which needs no outward/inward orientation that rounding
// could flip for slivers; the slabs and the grown box all hold the Minkowski sum of the triangle
// and the texel box, i.e. the centre of every touched texel. This shader emits one rectangle
// covering that region (aligned with the longest edge, so a diagonal sliver costs about its own
// area) and the fragment shader discards centres outside a slab or the box. Straight-line code:
// lavapipe compiles loops over local arrays in a geometry shader very slowly.
//
// Dilation: every support and the box grow by THIN_DILATE_TEXELS more, so a texel is covered when
// the triangle touches its 3x3 neighbourhood (shared/thin.h).
//
// Near plane: corners with z < 0 (behind Vulkan's near plane; w <= 0 behind the light) are clipped
// off in closed form before any divide, leaving a triangle or a quad whose near-plane corners have
// w = near > 0. Edge lines are built homogeneously (cross products of clip-space corners), so they
// stay exact even where those corners project far outside the face; the box is limited to the
// face. Such a clipped triangle is measured in world space instead (altitude and longest edge over
// the texel size at its farthest in-front corner), because its texel-space shape diverges near the
// near plane; its nearest corner is on the near plane, so it writes depth 0 (still conservative).
// Depth: the corners' range and the plane's depth gradient over texel coordinates, for the
// fragment shader (a triangle seen edge-on, or clipped, keeps its nearest corner's depth).
// Any corner left with w <= 0 (a projection neither perspective nor orthographic) drops it.
layout(triangles) in;
layout(triangle_strip, max_vertices = 4) out;
layout(location = 0) in vec3 inWorld[];
layout(location = 0) flat out vec4 outEdges[THIN_EDGES];
layout(location = THIN_EDGES) flat out vec4 outBox;
layout(location = THIN_EDGES + 1) flat out vec4 outDepth;      // x: nearest corner, y: farthest, zw: gradient
layout(location = THIN_EDGES + 2) flat out vec3 outDepthAt;   // xy: a corner's texel coordinates, z: its depth
layout(location = THIN_EDGES + 3) flat out uint outCutout;    // 1 + the CutoutTriangle whose alpha decides, or 0
layout(location = THIN_EDGES + 4) flat out vec3 outUvMap[3];  // thin_cutout.glsl's map, by columns
layout(push_constant) uniform PushBlock { ThinTrianglePush push; };

#include "thin_face.glsl"
#include "thin_cutout.glsl"

// Slab of edge a-b holding the corners q0..q3, as bounds on dot(normal, texel coordinates).
vec4 edgeSlab(vec4 a, vec4 b, vec4 q0, vec4 q1, vec4 q2, vec4 q3) {
  vec3 line = cross(a.xyw, b.xyw);  // line.x * X + line.y * Y + line.z = 0 in NDC
  vec2 gradient = 2.0 * line.xy / push.resolution;  // the same line over texel coordinates
  float len = length(gradient);
  if (!(len > 0.0)) return vec4(0.0, 0.0, -3.0e38, 3.0e38);  // a repeated corner: no constraint
  float k = 1.0 / len;
  vec2 normal = gradient * k;
  float constant = k * (line.z - line.x - line.y);  // signed distance = dot(normal, p) + constant
  vec4 d = k * vec4(dot(line, q0.xyw) / q0.w, dot(line, q1.xyw) / q1.w, dot(line, q2.xyw) / q2.w,
                    dot(line, q3.xyw) / q3.w);
  float lo = min(min(d.x, d.y), min(d.z, d.w));
  float hi = max(max(d.x, d.y), max(d.z, d.w));
  float support = (0.5 + THIN_DILATE_TEXELS) * (abs(normal.x) + abs(normal.y)) + THIN_EPSILON_TEXELS;
  return vec4(normal, lo - support - constant, hi + support - constant);
}

uint cutout = 0u;
mat3 uvMap = mat3(0.0);

void emit(vec2 corner, vec4 e0, vec4 e1, vec4 e2, vec4 e3, vec4 box, vec4 depth, vec3 depthAt) {
  gl_Position = vec4(corner / push.resolution * 2.0 - 1.0, depth.x, 1.0);
  outCutout = cutout;
  outUvMap[0] = uvMap[0];
  outUvMap[1] = uvMap[1];
  outUvMap[2] = uvMap[2];
  outEdges[0] = e0;
  outEdges[1] = e1;
  outEdges[2] = e2;
  outEdges[3] = e3;
  outBox = box;
  outDepth = depth;
  outDepthAt = depthAt;
  EmitVertex();
}

void main() {
  vec4 q0, q1, q2, q3;
  uint behind;
  bool thin;
  if (!thinOnFace(gl_in[0].gl_Position, gl_in[1].gl_Position, gl_in[2].gl_Position, inWorld[0], inWorld[1], inWorld[2], q0,
                  q1, q2, q3, behind, thin)) {
    return;
  }
  // A cut-out triangle that is not thin: its alpha decides per texel (a near-clipped one is kept whole).
  if (push.cutouts != 0u && !thin && behind == 0u) {
    uint index = push.firstCutout + uint(gl_PrimitiveIDIn);
    if (thinUvMap(gl_in[0].gl_Position, gl_in[1].gl_Position, gl_in[2].gl_Position, thinCutoutTriangle(index), uvMap)) {
      cutout = index + 1u;
    }
  }
  float res = push.resolution;
  vec2 p0 = texel(q0), p1 = texel(q1), p2 = texel(q2), p3 = texel(q3);
  vec2 lo = min(min(p0, p1), min(p2, p3));
  vec2 hi = max(max(p0, p1), max(p2, p3));
  float grow = 0.5 + THIN_DILATE_TEXELS + THIN_EPSILON_TEXELS;
  vec4 box = vec4(clamp(lo, -1.0, res + 1.0) - grow, clamp(hi, -1.0, res + 1.0) + grow);
  vec4 z = vec4(q0.z / q0.w, q1.z / q1.w, q2.z / q2.w, q3.z / q3.w);
  vec4 depth = vec4(clamp(min(min(z.x, z.y), min(z.z, z.w)), 0.0, 1.0), clamp(max(max(z.x, z.y), max(z.z, z.w)), 0.0, 1.0), 0.0, 0.0);
  {  // NDC depth is affine over a plane in texel coordinates: z = z0 + dot(g, p - p0)
    vec2 a = p1 - p0, b = p2 - p0;
    float det = a.x * b.y - a.y * b.x;
    vec2 g = vec2((z.y - z.x) * b.y - (z.z - z.x) * a.y, (z.z - z.x) * a.x - (z.y - z.x) * b.x) / det;
    if (behind == 0u && abs(det) > 1e-6 && !any(isinf(g)) && !any(isnan(g))) depth.zw = g;
  }
  vec3 depthAt = vec3(p0, depth.zw == vec2(0.0) ? depth.x : z.x);
  vec4 s0 = edgeSlab(q0, q1, q0, q1, q2, q3);
  vec4 s1 = edgeSlab(q1, q2, q0, q1, q2, q3);
  vec4 s2 = edgeSlab(q2, q3, q0, q1, q2, q3);
  vec4 s3 = edgeSlab(q3, q0, q0, q1, q2, q3);

  if (behind == 0u && all(greaterThan(lo, vec2(-res))) && all(lessThan(hi, vec2(2.0 * res)))) {
    // A rectangle along the longest edge u: the triangle's extent along u and across it, grown.
    vec2 e0 = p1 - p0, e1 = p2 - p1, e2 = p0 - p2;
    float l0 = dot(e0, e0), l1 = dot(e1, e1), l2 = dot(e2, e2);
    vec2 u = normalize(l0 >= l1 && l0 >= l2 ? e0 : (l1 >= l2 ? e1 : e2));
    vec2 v = vec2(-u.y, u.x);
    vec3 du = vec3(dot(u, p0), dot(u, p1), dot(u, p2));
    vec3 dv = vec3(dot(v, p0), dot(v, p1), dot(v, p2));
    float gu = (0.5 + THIN_DILATE_TEXELS) * (abs(u.x) + abs(u.y)) + THIN_EPSILON_TEXELS;
    float gv = (0.5 + THIN_DILATE_TEXELS) * (abs(v.x) + abs(v.y)) + THIN_EPSILON_TEXELS;
    float u0 = min(du.x, min(du.y, du.z)) - gu, u1 = max(du.x, max(du.y, du.z)) + gu;
    float v0 = min(dv.x, min(dv.y, dv.z)) - gv, v1 = max(dv.x, max(dv.y, dv.z)) + gv;
    emit(u * u0 + v * v0, s0, s1, s2, s3, box, depth, depthAt);
    emit(u * u1 + v * v0, s0, s1, s2, s3, box, depth, depthAt);
    emit(u * u0 + v * v1, s0, s1, s2, s3, box, depth, depthAt);
    emit(u * u1 + v * v1, s0, s1, s2, s3, box, depth, depthAt);
  } else {
    // Reaching far off the face: its part on the face lies in the (clamped) box.
    emit(box.xy, s0, s1, s2, s3, box, depth, depthAt);
    emit(box.zy, s0, s1, s2, s3, box, depth, depthAt);
    emit(box.xw, s0, s1, s2, s3, box, depth, depthAt);
    emit(box.zw, s0, s1, s2, s3, box, depth, depthAt);
  }
  EndPrimitive();
}
