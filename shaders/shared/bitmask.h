// Bitmask visibility sampling (Eisemann & Décoret 2007): the receiver plane, the light and the
// Hough table as raster/bitmask_pass and bitmask_{hidden,resolve} see them, one source for the
// shaders and the C++ side (which builds the table and checks it).
#ifndef PENUMBRA_SHARED_BITMASK_H
#define PENUMBRA_SHARED_BITMASK_H
#include "shared/glsl_cpp.h"
#include "shared/light.h"
PN_BEGIN

// Bindings (raster/bitmask_pass.cpp). bitmask_table.comp: the light and the table it writes.
#define BITMASK_TABLE_BINDING_LIGHT 0
#define BITMASK_TABLE_BINDING_TABLE 2
// bitmask_fit.comp: the G-buffer's position and normal, the BitmaskFrame it fits, the bounds.
#define BITMASK_FIT_BINDING_POSITION 0
#define BITMASK_FIT_BINDING_NORMAL 1
#define BITMASK_FIT_BINDING_FRAME 3
#define BITMASK_FIT_BINDING_BOUNDS 4
// The raster passes (bitmask_hidden.*, bitmask_height.*): the BitmaskFrame, the table, the hidden
// samples' bits, the fill counters and the height field.
#define BITMASK_DRAW_BINDING_FRAME 1
#define BITMASK_DRAW_BINDING_TABLE 2
#define BITMASK_DRAW_BINDING_HIDDEN 3
#define BITMASK_DRAW_BINDING_FILL 4
#define BITMASK_DRAW_BINDING_HEIGHTS 5
// bitmask_resolve.comp: the G-buffer, FrameData, the BitmaskFrame, the hidden bits, the visibility
// and trace flags it writes, the height field.
#define BITMASK_RESOLVE_BINDING_POSITION 0
#define BITMASK_RESOLVE_BINDING_NORMAL 1
#define BITMASK_RESOLVE_BINDING_FRAME_DATA 2
#define BITMASK_RESOLVE_BINDING_FRAME 3
#define BITMASK_RESOLVE_BINDING_HIDDEN 4
#define BITMASK_RESOLVE_BINDING_VISIBILITY 5
#define BITMASK_RESOLVE_BINDING_TRACE_FLAGS 6
#define BITMASK_RESOLVE_BINDING_HEIGHTS 7

// The Hough table: for each oriented line through the light's normalized square [-1/2, 1/2]^2,
// binned by its direction theta in [-pi, pi) and its signed distance r from the centre in
// [-BITMASK_R_MAX, BITMASK_R_MAX], the samples strictly left of it, BITMASK words of 32 bits.
#define BITMASK_THETA_BINS 1024u
#define BITMASK_R_BINS 512u
#define BITMASK_R_MAX 0.70710678f  // half the square's diagonal: lines farther off miss it
#define BITMASK_MAX_SAMPLES 1024u  // 32 words: the hidden-samples map of a 512^2 receiver is 32 MiB
#define BITMASK_GROUP_SIZE 16u     // bitmask_resolve.comp: 16x16 pixels per workgroup
#define BITMASK_TABLE_GROUP_SIZE 64  // bitmask_table.comp: table words per workgroup

// bitmask_table.comp's push constants.
struct BitmaskTablePush {
  uint samples;
  uint words;  // ceil(samples / 32)
};

// std430, 176 bytes: one receiver plane (or a height field over it) and the light, read by every
// bitmask shader.
struct BitmaskFrame {
  vec4 plane;        // receiver plane: xyz unit normal on the light's side, w: -dot(normal, a point on it)
  vec4 origin;       // xyz: world point at the map's (0, 0) corner
  vec4 axisU;        // xyz: unit world direction of the map's x; w: the map's world extent along it
  vec4 axisV;        // ... of its y
  vec4 lightCentre;  // xyz; w: light size along lightT (rect side, disk diameter)
  vec4 lightT;       // xyz: the light's first axis (GpuLight tangent); w: height of its lowest corner over the plane
  vec4 lightB;       // xyz: cross(direction, tangent); w: casters lie between the plane and the light, this far off both
  uint words;        // 32-bit words per hidden-samples texel: ceil(samples / 32)
  uint samples;
  uint resolution;   // the map's texels per side
  uint keepOthers;   // 1: the resolve leaves pixels off the receiver as the classification left them (fallback srt)
  vec4 onPlane;      // x: a pixel lies on the receiver within this distance of the plane; y: min cos to its
                     // normal; z: light size along lightB (a patch's second side; lightCentre.w for lights);
                     // w: 1 when the casters are watertight (front faces dropped)
  uint decorrelate;  // 1: each texel sees the pattern under one of the square's 8 symmetries (texelSymmetry)
  uint pad0, pad1, pad2;
  vec4 field;        // x: 1 for a height-field receiver (its surface's height over the plane per texel:
                     // bitmask_height.*), y: its greatest height over the plane
};

// Per-texel decorrelation (--bitmask-decorrelate): texel i's samples are the shared pattern under
// symmetry texelSymmetry(i) of the light's square (bit 0: swap the axes, then bit 1: negate x,
// bit 2: negate y), which keeps the light's shape and each sample's stratum size exactly, and
// turns the pattern's aliasing between texels into noise (the bilinear resolve averages four).
PN_FN uint texelSymmetry(BitmaskFrame f, uint texel) { return f.decorrelate != 0u ? pcgHash(texel) & 7u : 0u; }
PN_FN vec2 applySymmetry(uint s, vec2 q) {
  vec2 r = (s & 1u) != 0u ? vec2(q.y, q.x) : q;
  return vec2((s & 2u) != 0u ? -r.x : r.x, (s & 4u) != 0u ? -r.y : r.y);
}
PN_FN vec2 undoSymmetry(uint s, vec2 q) {
  vec2 r = vec2((s & 2u) != 0u ? -q.x : q.x, (s & 4u) != 0u ? -q.y : q.y);
  return (s & 1u) != 0u ? vec2(r.y, r.x) : r;
}

// The oriented line from a to b (a != b) in Hough coordinates: its direction theta in (-pi, pi]
// and its signed distance r from the centre (r < -R: every sample is left of it; r > R: none).
PN_FN vec2 houghLine(vec2 a, vec2 b) {
  vec2 d = b - a;
  return vec2(atan(d.y, d.x), dot(a, vec2(-d.y, d.x)) / length(d));
}

// Index of the Hough bin holding a line (theta, r), r clamped to the table.
PN_FN uint houghBin(vec2 line) {
  uint ti = uint(floor((line.x + 3.14159265f) * (float(BITMASK_THETA_BINS) / 6.28318531f))) % BITMASK_THETA_BINS;
  float rf = (line.y + BITMASK_R_MAX) * (float(BITMASK_R_BINS) / (2.0f * BITMASK_R_MAX));
  return ti * BITMASK_R_BINS + uint(clamp(floor(rf), 0.0f, float(BITMASK_R_BINS - 1u)));
}

// The bin of the same line reversed: theta + pi, -r. The table holds there the exact complement of
// the bin's samples, so that two triangles sharing an edge (traversed in opposite directions) hide
// every sample between them: bitmask_hidden.frag bins an edge from its endpoints in a fixed order
// and takes the opposite bin for the other direction.
PN_FN uint houghOpposite(uint bin) {
  uint ti = bin / BITMASK_R_BINS, ri = bin % BITMASK_R_BINS;
  return ((ti + BITMASK_THETA_BINS / 2u) % BITMASK_THETA_BINS) * BITMASK_R_BINS + (BITMASK_R_BINS - 1u - ri);
}

// The line at the centre of bin (ti, ri): its left normal and offset; sample q is left of it when
// dot(q, left) > r.
PN_FN vec3 houghBinLine(uint ti, uint ri) {
  float theta = -3.14159265f + (float(ti) + 0.5f) * (6.28318531f / float(BITMASK_THETA_BINS));
  float r = -BITMASK_R_MAX + (float(ri) + 0.5f) * (2.0f * BITMASK_R_MAX / float(BITMASK_R_BINS));
  return vec3(-sin(theta), cos(theta), r);
}

// Corner i (0..3) of the light's square (a disk's bounding square, a source patch's rectangle).
PN_FN vec3 lightSquareCorner(BitmaskFrame f, int i) {
  vec2 h = 0.5f * vec2(f.lightCentre.w, f.onPlane.z);
  return vec3(f.lightCentre) + ((i & 1) != 0 ? h.x : -h.x) * vec3(f.lightT) + ((i & 2) != 0 ? h.y : -h.y) * vec3(f.lightB);
}

// Point p on the receiver's map: [0, 1)^2 inside it.
PN_FN vec2 receiverUv(BitmaskFrame f, vec3 p) {
  vec3 d = p - vec3(f.origin);
  return vec2(dot(d, vec3(f.axisU)) / f.axisU.w, dot(d, vec3(f.axisV)) / f.axisV.w);
}

// Whether surface point p (normal n, map coordinates uv) lies on the receiver: inside its map,
// within onPlane.x of its surface (of height `height` over the plane there; 0 for a plane), and
// facing the plane's side (a plane: within onPlane.y of its normal; a height field: at all).
PN_FN bool onReceiver(BitmaskFrame f, vec3 p, vec3 n, vec2 uv, float height, float tolerance) {
  float facing = f.field.x != 0.0f ? 0.0f : f.onPlane.y;
  return abs(dot(vec3(f.plane), p) + f.plane.w - height) <= f.onPlane.x + tolerance && dot(n, vec3(f.plane)) > facing &&
         uv.x >= 0.0f && uv.y >= 0.0f && uv.x < 1.0f && uv.y < 1.0f;
}

PN_END
#endif
