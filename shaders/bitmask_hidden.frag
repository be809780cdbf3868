#version 450
// Bitmask visibility sampling (Eisemann & Décoret 2007, section 4): at the receiver point of this
// texel's centre, the caster triangle back-projected onto the light's normalized square, oriented
// counter-clockwise; the samples it hides are those left of all its edges: the AND of the Hough
// table's masks for the edge lines, ORed into the texel's hidden-samples bits.
// The triangle is first clipped to the receiver point's side of the light: under a light tilted
// against the receiver, part of a long caster can lie behind the point (level with it or farther
// from the light's plane), where the projection through the point would throw it to infinity or
// onto the wrong side; that part cannot block the point's rays. Clipping leaves a triangle or a
// quad (four edges).
#extension GL_GOOGLE_include_directive : require
#include "shared/bitmask.h"
layout(location = 0) flat in vec3 inA;
layout(location = 1) flat in vec3 inB;
layout(location = 2) flat in vec3 inC;
layout(std430, binding = BITMASK_DRAW_BINDING_FRAME) readonly buffer Frame { BitmaskFrame frame; };
layout(std430, binding = BITMASK_DRAW_BINDING_TABLE) readonly buffer Table { uint table[]; };
layout(std430, binding = BITMASK_DRAW_BINDING_HIDDEN) buffer Hidden { uint hidden[]; };
layout(std430, binding = BITMASK_DRAW_BINDING_HEIGHTS) readonly buffer Heights { float heights[]; };  // a height field's, per texel

// A caster point must lie at least this fraction of the way from the receiver point to the light's plane.
const float kAhead = 1e-4;

void main() {
  uint res = frame.resolution;
  vec2 uv = gl_FragCoord.xy / float(res);
  vec3 x = frame.origin.xyz + uv.x * frame.axisU.w * frame.axisU.xyz + uv.y * frame.axisV.w * frame.axisV.xyz;
  uint texel = uint(gl_FragCoord.y) * res + uint(gl_FragCoord.x);
  if (frame.field.x != 0.0) x += heights[texel] * frame.plane.xyz;  // the field's surface over the texel
  vec3 t = frame.lightT.xyz, b = frame.lightB.xyz, centre = frame.lightCentre.xyz;
  vec3 direction = cross(t, b);
  float toLight = dot(direction, centre - x);
  // Caster points nearer to x than the caster margin along the light's axis are x's own surface
  // (the reference's rays start that far off it): a height field's neighbouring triangles.
  float ahead = max(kAhead, frame.lightB.w / toLight);
  // How far each corner is along the way from x to the light's plane (1: on it).
  float ka = dot(direction, inA - x) / toLight, kb = dot(direction, inB - x) / toLight, kc = dot(direction, inC - x) / toLight;
  uint inside = uint(ka > ahead) + uint(kb > ahead) + uint(kc > ahead);
  if (inside == 0u) return;
  // The clipped polygon, odd corner first (as bitmask_hidden.geom clips).
  vec3 p = inA, q = inB, r = inC;
  float kp = ka, kq = kb, kr = kc;
  bool one = inside == 1u;
  if (inside != 3u) {
    if ((kb > ahead) == one) {
      p = inB; q = inC; r = inA; kp = kb; kq = kc; kr = ka;
    } else if ((kc > ahead) == one) {
      p = inC; q = inA; r = inB; kp = kc; kq = ka; kr = kb;
    }
  }
  vec3 pq = mix(p, q, (kp - ahead) / (kp - kq)), pr = mix(p, r, (kp - ahead) / (kp - kr));
  vec3 c0 = p, c1 = q, c2 = r, c3 = r;  // a triangle repeats its last corner
  uint corners = 3u;
  if (inside == 1u) {
    c1 = pq;
    c2 = pr;
    c3 = pr;
  } else if (inside == 2u) {
    c0 = pq;
    c3 = pr;
    corners = 4u;
  }
  // Corner c seen from x on the light's plane, in units of its size from its centre.
  // With decorrelation the texel's samples are the pattern under its symmetry S: sample S(q) lies
  // in the triangle iff q lies in S^-1 of it.
  uint symmetry = texelSymmetry(frame, texel);
  vec2 l[4];
  vec3 cs[4] = vec3[4](c0, c1, c2, c3);
  for (uint i = 0u; i < 4u; ++i) {
    vec3 on = x + (cs[i] - x) / (dot(direction, cs[i] - x) / toLight);
    l[i] = undoSymmetry(symmetry, vec2(dot(on - centre, t), dot(on - centre, b)) / vec2(frame.lightCentre.w, frame.onPlane.z));
  }
  float area = 0.0;  // twice the signed area (shoelace)
  for (uint i = 0u; i < corners; ++i) {
    vec2 u = l[i], v = l[(i + 1u) % corners];
    area += u.x * v.y - u.y * v.x;
  }
  if (!(abs(area) > 1e-12)) return;  // edge-on from x (or not finite): hides nothing
  uint bins[4];
  bool all[4];
  for (uint i = 0u; i < corners; ++i) {
    vec2 from = l[i], to = l[(i + 1u) % corners];
    if (area < 0.0) {  // interior on the left
      vec2 swap = from;
      from = to;
      to = swap;
    }
    // Binned from its endpoints in a fixed order (see houghOpposite): an edge shared with a
    // neighbouring triangle gets the exact complement of that triangle's mask.
    bool reversed = from.x > to.x || (from.x == to.x && from.y > to.y);
    vec2 line = reversed ? houghLine(to, from) : houghLine(from, to);
    float r = reversed ? -line.y : line.y;
    if (r >= BITMASK_R_MAX) return;  // the caster's shadow misses the light
    all[i] = r <= -BITMASK_R_MAX;
    bins[i] = reversed ? houghOpposite(houghBin(line)) : houghBin(line);
  }
  uint words = frame.words;
  texel *= words;
  for (uint w = 0u; w < words; ++w) {
    uint m = ~0u;
    for (uint i = 0u; i < corners; ++i) m &= all[i] ? ~0u : table[bins[i] * words + w];
    if (m != 0u) atomicOr(hidden[texel + w], m);
  }
}
