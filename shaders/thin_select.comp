#version 450
// Thin-triangle selection: one invocation per scene triangle finds, for one light face, whether
// the conservative raster (thin_triangles.geom) would keep it, and appends the thin ones' indices
// to the face's list, so that pass draws only them. Order does not matter: the mask is a depth
// minimum. Past the list's capacity the face falls back to drawing the whole scene.
#extension GL_GOOGLE_include_directive : require
#include "shared/thin.h"
layout(local_size_x = THIN_SELECT_GROUP_SIZE) in;
layout(std430, binding = THIN_SELECT_BINDING_VERTICES) readonly buffer Vertices { float vertices[]; };  // RasterVertex: 9 floats, position first
layout(std430, binding = THIN_SELECT_BINDING_INDICES) readonly buffer Indices { uint indices[]; };
layout(std430, binding = THIN_SELECT_BINDING_DRAWS) buffer Draws { uint draws[]; };
layout(std430, binding = THIN_SELECT_BINDING_LIST) writeonly buffer List { uint list[]; };
layout(push_constant) uniform PushBlock { ThinSelectPush select; };
#define push select.thin
#include "thin_face.glsl"

vec3 corner(uint index) { return vec3(vertices[9u * index], vertices[9u * index + 1u], vertices[9u * index + 2u]); }

void main() {
  uint tri = gl_GlobalInvocationID.y * select.rowInvocations + gl_GlobalInvocationID.x;
  if (tri >= select.triangles) return;
  uint i0 = indices[3u * tri], i1 = indices[3u * tri + 1u], i2 = indices[3u * tri + 2u];
  vec3 w0 = corner(i0), w1 = corner(i1), w2 = corner(i2);
  vec4 q0, q1, q2, q3;
  uint behind;
  bool thin;
  if (!thinOnFace(push.viewProj * vec4(w0, 1.0), push.viewProj * vec4(w1, 1.0), push.viewProj * vec4(w2, 1.0), w0, w1,
                  w2, q0, q1, q2, q3, behind, thin)) {
    return;
  }
  uint base = select.face * THIN_DRAW_WORDS;
  uint slot = atomicAdd(draws[base + THIN_DRAW_COUNT], 1u);
  if (slot < select.capacity) {
    uint at = 3u * (select.face * select.capacity + slot);
    list[at] = i0;
    list[at + 1u] = i1;
    list[at + 2u] = i2;
    atomicAdd(draws[base + THIN_DRAW_LIST], 3u);  // counts written triangles only
  } else {
    draws[base + THIN_DRAW_ALL] = 3u * select.triangles;  // overflow: the face draws everything
  }
}
