#version 450
// PIP classification (Lauterbach et al. 2009, 3.1) fused with the plain shadow-map answer.
// Per covered pixel: the shadow-map visibility (as method sm), and whether it may be wrong:
//  - a depth edge in the 3x3 texel neighbourhood (max |s - s'| > threshold) that the receiver's
//    depth interval [d-hat, d] within one texel can reach: d-hat = d sin(b) / sin(a + b) for a
//    texel of angle a (perspective), d - w cot(b) for a texel of width w (orthographic), with
//    sin(b) = n.L;
//  - a thin triangle, rasterized conservatively, covering the neighbourhood in front of it;
//  - a neighbourhood that leaves its cube face (seams are classified conservatively);
//  - beyond the paper, what the depth test lets through on real content: another surface over the
//    receiver within the bias - a surface rising beside it, a step's foot, a strip lying on it
//    (contact; layerOver) - light through a gap between blockers narrower than a texel, which
//    the map closes (gapBetweenBlockers), and an umbra whose blocker lies within the receiver's
//    own depth interval (acne the bias left, as under a spot's wide perspective texels).
// For hard shadows it can also bound the ray: blockers in the texel column are no closer to the
// light than the neighbourhood's minimum depth (less its spread and two texels), so the ray stops there.
// Area lights (3.2): the penumbra mask is the union of the edge texels' splats, each the light's
// shape scaled by the edge's depth relative to the receiver; computed here by gathering instead of
// splatting: a pixel is in the mask iff an edge texel nearer than the receiver lies where its
// splat covers the pixel, i.e. on a segment from the pixel's point to the light, searched in the
// edge pyramid (penumbra_mask.glsl) in every face of the map; beyond the paper, also iff a smooth
// surface without an edge rises over a lit receiver's plane there, or part of the light is below
// the plane of the receiver's face (a smoothed mesh's shading normal leans off it).
// Outside the mask a pixel is lit (no blocker within reach) or umbra (only blockers, no edge)
// unless its umbra's blocker lies within its own depth interval (acne: traced, as is a layer
// within the bias over a lit receiver).
// With --penumbra-maps 5 the pass runs again on maps from the light's four corners, each adding
// its edges' splats to the mask (cornerUnion).
// With PipPush::appendList the flagged pixels also go straight into the trace list (ShadingPoints
// and their count), so that no compaction pass has to read every pixel's flags again.
// Area lights, with PipPush::tileTraceBelow (the tile choice): a tile of PIP_MASK_TILE_SIZE^2
// pixels that the last frame found (nearly) all doubtful is traced whole - every pixel flagged,
// none searched - where the host's cost model says that is cheaper (FrameContext::reportTileChoice); the
// others count their covered and flagged pixels for the next frame's choice (pip_tiles.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#include "shared/frame.h"
#include "shared/pip.h"
#include "shared/pyramid.h"
#include "shared/shading_point.h"
#include "shared/trace.h"
layout(local_size_x = PIP_GROUP_SIZE, local_size_y = PIP_GROUP_SIZE) in;
layout(binding = PIP_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(binding = PIP_BINDING_NORMAL, rgba32f) uniform readonly image2D gNormal;
layout(binding = PIP_BINDING_FACE_NORMAL, r32ui) uniform readonly uimage2D gFaceNormal;
layout(binding = PIP_BINDING_SHADOW_MAP) uniform sampler2DArray shadowMap;
layout(binding = PIP_BINDING_THIN_MASK) uniform sampler2DArray thinMask;
layout(std430, binding = PIP_BINDING_FRAME) readonly buffer Frame { FrameData frame; };
layout(std430, binding = PIP_BINDING_VISIBILITY) buffer Visibility { float visibility[]; };
layout(std430, binding = PIP_BINDING_SM_VISIBILITY) writeonly buffer ShadowMapVisibility { float smVisibility[]; };
layout(std430, binding = PIP_BINDING_TRACE_FLAGS) buffer TraceFlags { uint traceFlags[]; };
layout(std430, binding = PIP_BINDING_RAY_MAX) writeonly buffer RayMax { float rayMax[]; };
// Read through the device addresses in PipPush; as macros, LIGHT_TEXEL and the mask's search
// index them like the arrays they were.
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer Floats { float v[]; };
#define shadowTexels Floats(push.shadowTexelsAt).v
#define thinTexels Floats(push.thinTexelsAt).v
#define tiles Floats(push.tilesAt).v
layout(std430, binding = PIP_BINDING_COUNT) buffer Count { TraceCount traceCount; };
layout(std430, binding = PIP_BINDING_WHY) writeonly buffer Why { uint why[]; };
layout(push_constant) uniform PushBlock { PipPush push; };
// PipSettings::explain as a pipeline constant (raster/pip_classify_pass.cpp picks the pipeline by it),
// the only form this shader reads: a dispatch that does not explain compiles without the `why`
// writes and with a mask search that stops at its first rule.
layout(constant_id = 1) const bool kExplain = false;
// The dispatch before the pixels' where PipPush::tileTest: one invocation per tile, maskTile.
layout(constant_id = 2) const bool kTilePass = false;
#include "point_list.glsl"
#include "light_texels.glsl"
#include "receiver_plane.glsl"

float linearDepth(float z) {
  return linearShadowDepth(frame.shadow.kind, frame.shadow.nearPlane, frame.shadow.farPlane, z);
}
// Its inverse: the raw (NDC) depth of linear depth z.
float rawDepth(float z) {
  return rawShadowDepth(frame.shadow.kind, frame.shadow.nearPlane, frame.shadow.farPlane, z);
}

// Depth along the face axis, from clip coordinates (affine in world space for both projections).
float axisDepth(vec4 clip) {
  return frame.shadow.kind == SHADOW_ORTHO ? linearDepth(clip.z) : clip.w;
}
float axisDepthRate(vec4 clipDir) {
  return frame.shadow.kind == SHADOW_ORTHO ? clipDir.z * (frame.shadow.farPlane - frame.shadow.nearPlane) : clipDir.w;
}
// The receiver p's plane (face normal nf) in the map of viewProj, for the mask's surface search:
// its depth at texel coordinates e is s0 + dot(g, e - e0) in the map's affine depth measure s
// (orthographic: linear depth; perspective: -1/w, so that 1/w, affine along the plane, is not
// read back through NDC depth, whose float steps near 1 blur a plane extrapolated over tens of
// texels: a groove's wall 0.011 above a wall point 36 texels away was lost that way). A surface
// stands over the plane where its s is lower by more than tol: PIP_LAYER_TOLERANCE of the margin,
// or 4 steps of the stored depth. g is not finite when the plane is edge-on to the light.
struct MapPlane {
  float s0, tol;
  vec2 e0, gLo, gHi;  // one receiver: gLo = gHi = g; a tile's plane (maskTile) bounds its receivers' g
  float raw0;   // p's raw depth (at e0)
  vec2 sOfRaw;  // s = sOfRaw.x + sOfRaw.y * raw depth
};
float planeDepthMeasure(vec4 clip) {
  return frame.shadow.kind == SHADOW_ORTHO ? linearDepth(clip.z / clip.w) : -1.0 / clip.w;
}
// s of the raw depth: s = planeDepthOfRaw().x + planeDepthOfRaw().y * raw.
vec2 planeDepthOfRaw() {
  float near = frame.shadow.nearPlane, far = frame.shadow.farPlane;
  return frame.shadow.kind == SHADOW_ORTHO ? vec2(near, far - near) : vec2(-1.0 / near, (far - near) / (near * far));
}
// No plane: the edge channel's search reads none.
const MapPlane kNoPlane = MapPlane(0.0, 0.0, vec2(0.0), vec2(0.0), vec2(0.0), 0.0, vec2(0.0));
MapPlane mapPlane(vec3 p, vec3 nf, float texel, mat4 viewProj) {
  float res = float(frame.shadow.resolution);
  bool ortho = frame.shadow.kind == SHADOW_ORTHO;
  MapPlane plane;
  vec4 c0 = viewProj * vec4(p, 1.0);
  plane.e0 = (c0.xy / c0.w * 0.5 + 0.5) * res;
  plane.s0 = planeDepthMeasure(c0);
  plane.raw0 = c0.z / c0.w;
  // g with dot(g, e_i) = s_i - s0 for two points on the plane a texel from p
  vec3 t1 = normalize(cross(nf, abs(nf.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0)));
  vec4 c1 = viewProj * vec4(p + texel * t1, 1.0), c2 = viewProj * vec4(p + texel * cross(nf, t1), 1.0);
  vec2 e1 = (c1.xy / c1.w * 0.5 + 0.5) * res - plane.e0, e2 = (c2.xy / c2.w * 0.5 + 0.5) * res - plane.e0;
  float s1 = planeDepthMeasure(c1) - plane.s0, s2 = planeDepthMeasure(c2) - plane.s0;
  plane.gLo = plane.gHi = vec2(s1 * e2.y - s2 * e1.y, e1.x * s2 - e2.x * s1) / (e1.x * e2.y - e1.y * e2.x);
  plane.sOfRaw = planeDepthOfRaw();
  float perUnit = ortho ? 1.0 : 1.0 / (c0.w * c0.w);  // ds per world unit of depth at p
  float raw = c0.z / c0.w;
  plane.tol = PIP_LAYER_TOLERANCE * push.depthMargin * perUnit + 4.0 * (uintBitsToFloat(floatBitsToUint(raw) + 1u) - raw) * plane.sOfRaw.y;
  return plane;
}
#include "penumbra_mask.glsl"

// Whether the map holds another surface over the receiver p (face normal nf), nearer to the light
// than p's own plane by more than the test's resolution (PIP_LAYER_TOLERANCE of the margin, or 4
// steps of the stored depth), however little: a step whose foot p stands at, a decal or strip
// lying on p's surface, a leaf through a leaf. Depth bias cannot tell such a layer from p. All in
// NDC depth, where planes are affine in texel coordinates, around p's own texel, with the map's
// slope-scaled bias taken off each sample (frame.shadow.slopeBias; 0 by default). A layer is:
//  - the surface of p's texel, or of the texel sm read (t), nearer than p's plane at its centre, or
//  - the surface of a neighbour q (an edge neighbour, or the diagonal one on p's side; its plane
//    from q and the texels beyond it) that lies nearer than p's plane both at q and, extended, at
//    p. A crease of one surface is nearer at one end only (its planes cross between p and q), so
//    it is not a layer.
// Without a slope bias, a neighbour not nearer than p's plane at its centre needs no plane of its
// own (its reads are skipped).
bool layerOver(vec3 p, vec3 nf, float texel, mat4 viewProj, uint face, ivec2 t) {
  int res = int(frame.shadow.resolution);
  vec4 c0 = viewProj * vec4(p, 1.0);
  float z0 = c0.z / c0.w;
  vec2 e0 = (c0.xy / c0.w * 0.5 + 0.5) * float(res);
  vec2 g = planeDepthGradient(p, nf, texel, viewProj, e0, z0);
  float slope = frame.shadow.slopeBias;
#define DEPTH_AT(q) LIGHT_TEXEL(shadowMap, shadowTexels, clamp(q, ivec2(0), ivec2(res - 1)), face, res)
  ivec2 tp = clamp(ivec2(floor(e0)), ivec2(0), ivec2(res - 1));
  vec2 f = e0 - (vec2(tp) + 0.5);  // p from its texel's centre, in texels
  float raw = DEPTH_AT(tp);
  float near = frame.shadow.nearPlane, far = frame.shadow.farPlane, w = linearDepth(raw);
  float ndcPerUnit = frame.shadow.kind == SHADOW_ORTHO ? 1.0 / (far - near) : far * near / ((far - near) * w * w);
  float tol = PIP_LAYER_TOLERANCE * push.depthMargin * ndcPerUnit + 4.0 * (uintBitsToFloat(floatBitsToUint(raw) + 1u) - raw);
  float centreBias = slope * max(abs(g.x), abs(g.y));
  float atCentre = z0 - dot(g, f);  // p's plane at tp's centre
  if (atCentre - (raw - centreBias) > tol) return true;
  // The texel sm read (the normal offset may move it off p's own): its surface nearer than p's
  // plane there is what made a lit receiver dark, or would make it so.
  if (t != tp && (z0 + dot(g, vec2(t - tp) - f)) - (DEPTH_AT(t) - centreBias) > tol) return true;
  ivec2 corner = ivec2(f.x < 0.0 ? -1 : 1, f.y < 0.0 ? -1 : 1);
  const ivec2 dx = ivec2(1, 0), dy = ivec2(0, 1);
  for (int k = 0; k < 5; ++k) {
    // dx, -dx, dy, -dy, corner (no local array: lavapipe keeps one indexed by k in scratch memory,
    // read lane by lane)
    ivec2 o = k == 4 ? corner : ivec2(k == 0 ? 1 : k == 1 ? -1 : 0, k == 2 ? 1 : k == 3 ? -1 : 0), q = tp + o;
    float zq = DEPTH_AT(q);
    float over = z0 + dot(g, vec2(o) - f) - zq;  // how much nearer than p's plane q's texel lies
    if (slope == 0.0 && !(over > tol)) continue;  // a bias could only move zq nearer
    // q's plane: outward differences along the axes it steps on, central ones across.
    vec2 gq = vec2(o.x != 0 ? (DEPTH_AT(q + ivec2(o.x, 0)) - zq) * float(o.x) : 0.5 * (DEPTH_AT(q + dx) - DEPTH_AT(q - dx)),
                   o.y != 0 ? (DEPTH_AT(q + ivec2(0, o.y)) - zq) * float(o.y) : 0.5 * (DEPTH_AT(q + dy) - DEPTH_AT(q - dy)));
    float qBias = slope * max(abs(gq.x), abs(gq.y));
    if (over + qBias > tol && z0 - (zq - qBias + dot(gq, f - vec2(o))) > tol) return true;
  }
#undef DEPTH_AT
  return false;
}

// Whether light may reach a receiver in umbra (point p, on `face`) through a gap between blockers
// narrower than a texel, which the map closes: the four texels around p's own point hold depths
// further apart than the edge threshold, so p's light ray passes between two surfaces' texels and
// the map cannot tell whether they meet (leaves side by side on a tree's crown). The 2x2
// footprint, not the 3x3: the gap must separate the texel centres nearest to p's point. A gap in
// one surface (all four alike) stays unseen, like a blocker the map lacks. Area lights need no
// such test: an edge texel nearer than the receiver puts it in the penumbra mask.
bool gapBetweenBlockers(vec3 p, mat4 viewProj, uint face) {
  int res = int(frame.shadow.resolution);
  vec4 c = viewProj * vec4(p, 1.0);
  ivec2 q = ivec2(floor((c.xy / c.w * 0.5 + 0.5) * float(res) - 0.5));
  float lo = 1.0, hi = 0.0;
  for (int k = 0; k < 4; ++k) {
    float z = LIGHT_TEXEL(shadowMap, shadowTexels, clamp(q + ivec2(k & 1, k >> 1), ivec2(0), ivec2(res - 1)), face, res);
    lo = min(lo, z);
    hi = max(hi, z);
  }
  return linearDepth(hi) - linearDepth(lo) > push.deltaThreshold;
}

// Whether a blocker may hide part of an area light from the receiver p (face normal nf; offsetP
// its point in the map, on `face` at texel t), searched in every face of the map, p's own first:
// an edge texel whose splat covers p, a layer over a lit p within the bias (layerOver), a surface
// rising over a lit p's plane (the surface channel). A cube map's other faces are searched too,
// in their own projections (p may lie outside them): a large light's cone from p crosses into
// them, and a blocker there has no texel in p's face (the bunny's ears under a light half the
// scene wide: blockers ~240 texels away across a face's border). This replaces marking every
// pixel whose window leaves its face (bunny, light 0.5: mask 89% -> 72% of covered pixels).
// halfExtent: the light's points lie within it of its centre. Returns the rules that found one
// (PIP_MASK_SPLAT, PIP_MASK_SURFACE), 0 for none: the first found, or with `every` all of them.
// tileClear: maskTile found no blocker within reach of any receiver of p's tile (a map of one
// face), so only layerOver is left to test.
uint blockerWithinReach(vec3 p, vec3 offsetP, vec3 nf, float texel, uint face, bool lit, bool interior, ivec2 t,
                        float halfExtent, bool every, bool tileClear) {
  uint res = frame.shadow.resolution, faces = frame.shadow.faceCount;
  uint rules = 0u;
#define FOUND(rule) { rules |= rule; if (!every) return rules; }
  for (uint i = 0u; i < faces; ++i) {
    uint f = (face + i) % faces;
    mat4 viewProj = faceViewProj(f);
    vec4 clip = viewProj * vec4(offsetP, 1.0);
    if (clip.w <= 0.0) {
      // p behind the face's eye (another cube face): p's segments to the light reach depths below
      // halfExtent there, so only a texel that near may block.
      float nearest = tiles[2u * (pyramidOffset(res, faces, push.pyramidLevels) + f) + PYRAMID_SURFACE];
      if (linearDepth(nearest) < halfExtent) FOUND(PIP_MASK_SPLAT);
      continue;
    }
    ivec2 tf = i == 0u ? t : ivec2(floor((clip.xy / clip.w * 0.5 + 0.5) * float(res)));
    float d = axisDepth(clip);
    SplatCone cone = splatCone(offsetP, viewProj, tf);  // one cone for both channels
    if (!tileClear && withinReach(cone, f, d, PYRAMID_EDGES, kNoPlane).x > 0.0) FOUND(PIP_MASK_SPLAT);
    if (!lit) continue;
    if (i == 0u && interior && layerOver(p, nf, texel, viewProj, f, t)) FOUND(PIP_MASK_SURFACE);
    if (!tileClear && withinReach(cone, f, d, PYRAMID_SURFACE, mapPlane(p, nf, texel, viewProj)).x > 0.0) {
      FOUND(PIP_MASK_SURFACE);
    }
  }
#undef FOUND
  return rules;
}

// Unflagged pixels keep the sm answer in `visibility`, so only flagged ones (which the trace
// overwrites) store it again, and only they need a ray end.
uint write(uint index, float vis, uint flags, float maxDistance, out float rayEnd) {
  visibility[index] = vis;
  traceFlags[index] = flags;
  rayEnd = maxDistance;
  if (flags != 0u) {
    smVisibility[index] = vis;
    if (push.appendList == 0u) rayMax[index] = maxDistance;  // for the compaction; the list carries it
  }
  return flags;
}

// p's point in the light's map: offset along n by the map's normal offset, on `face` at texel t
// (clip: its clip coordinates there). inside: within the map's square and depth range.
struct MapPoint {
  uint face;
  float texel;  // a texel's world size at p
  vec3 offsetP;
  vec4 clip;
  ivec2 t;
  bool inside;
};
MapPoint mapPoint(vec3 p, vec3 n) {
  MapPoint m;
  uint kind = frame.shadow.kind;
  m.face = shadowFace(kind, frame.shadow.lightPosition, p);
  m.texel = shadowTexelWorld(kind, frame.shadow.texelWorld, frame.shadow.lightPosition, p);
  m.offsetP = p + n * (frame.shadow.normalOffset * m.texel);
  m.clip = faceViewProj(m.face) * vec4(m.offsetP, 1.0);
  vec3 ndc = m.clip.xyz / m.clip.w;
  vec2 uv = ndc.xy * 0.5 + 0.5;
  m.inside = !(m.clip.w <= 0.0 || any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))) || ndc.z > 1.0);
  m.t = ivec2(floor(uv * float(frame.shadow.resolution)));
  return m;
}

// Classifies the pixel at `index` (covered: p, n) and writes its outputs; returns its flags.
// tileClear: the mask's tile test found no blocker within reach of any pixel of its tile.
uint classify(uint index, ivec2 pix, vec3 p, vec3 n, vec3 nf, bool tileClear, bool wholeTile, out float rayEnd) {
  rayEnd = 0.0;
  // A corner map (--penumbra-maps 5) only adds its edges' splats to the centre pass's mask.
  bool corner = push.cornerUnion != 0u;
  GpuLight light = frame.light;
  bool area = isAreaLight(light);
  float halfExtent = light.type == LIGHT_RECT ? light.size * 0.70710678 : light.size * 0.5;
  float facing = dot(n, light.position.xyz - p);  // > halfExtent: every light point is above the tangent plane
  // --light-error: the light's shadow changes this pixel's shade by less than it: the map's answer stands
  bool slight = frame.lightError > 0.0 && shadowWeight(light, p, n) < frame.lightError;
  if (!lightReaches(light, p, n, light.position.xyz)) {
    // An area light may still be partly above the receiver's tangent plane: trace those.
    bool partly = !slight && area && facing > -halfExtent && dot(p - light.position.xyz, light.direction.xyz) > 0.0;
    if (kExplain && !corner) why[index] = partly ? PIP_MASK_TANGENT : PIP_WHY_FACING;
    return corner ? 0u : write(index, 0.0, partly ? PIP_PENUMBRA : 0u, 0.0, rayEnd);
  }

  uint kind = frame.shadow.kind;
  MapPoint m = mapPoint(p, n);
  if (!m.inside) return corner ? 0u : write(index, 1.0, slight ? 0u : PIP_OUTSIDE, 0.0, rayEnd);
  uint face = m.face;
  float texel = m.texel;
  vec3 offsetP = m.offsetP;
  mat4 viewProj = faceViewProj(face);
  vec3 ndc = m.clip.xyz / m.clip.w;
  int res = int(frame.shadow.resolution);
  ivec2 t = m.t;
  if (corner && slight) return 0u;
  if (corner) {
    vec2 window = withinReach(splatCone(offsetP, viewProj, t), face, linearDepth(ndc.z), PYRAMID_EDGES, kNoPlane);
    if (window.x > 0.0 || (window.y > 0.0 && kind == SHADOW_CUBE)) {
      // A pixel the centre pass left unflagged has its sm answer in `visibility` only and no ray
      // end (write() stores both for flagged pixels); the trace and the stats need them.
      if (traceFlags[index] == 0u) {
        smVisibility[index] = visibility[index];
        rayMax[index] = 0.0;
        if (kExplain) why[index] = PIP_MASK_CORNER;
      }
      traceFlags[index] |= PIP_PENUMBRA;
    }
    return 0u;
  }
  float raw = LIGHT_TEXEL(shadowMap, shadowTexels, clamp(t, ivec2(0), ivec2(res - 1)), face, res);
  float vis = ndc.z <= raw ? 1.0 : 0.0;  // exactly the sm answer
  if (slight) {
    if (kExplain) why[index] = PIP_WHY_LIGHT_ERROR;
    return write(index, vis, 0u, 0.0, rayEnd);
  }
  if (wholeTile) return write(index, vis, PIP_PENUMBRA, 0.0, rayEnd);  // the tile choice traces it: no search

  uint flags = 0u;
  float thinDepth = frame.shadow.farPlane;
  if (push.useThin != 0u) {  // the mask is dilated: this texel holds its 3x3 neighbourhood's nearest thin triangle
    float thin = LIGHT_TEXEL(thinMask, thinTexels, clamp(t, ivec2(0), ivec2(res - 1)), face, res);
    if (thin < ndc.z) flags |= PIP_THIN;
    thinDepth = linearDepth(thin);
  }

  float d = linearDepth(ndc.z);
  bool interior = all(greaterThan(t, ivec2(0))) && all(lessThan(t, ivec2(res - 1)));
  // The receiver's depth interval within its texel, [d-hat, d] (sin(a + b) expanded: no asin).
  vec3 l = directionToLight(light, p, light.position.xyz);
  float sinB = clamp(dot(n, l), 1e-4, 1.0);
  float cosB = sqrt(max(1.0 - sinB * sinB, 0.0));
  float a = frame.shadow.texelWorld;
  float dHat = kind == SHADOW_ORTHO ? d - texel * cosB / sinB : d * sinB / (sin(a) * cosB + cos(a) * sinB);
  float lo = min(dHat, d) - push.depthMargin;
  float hi = d + push.depthMargin;
  float s = linearDepth(raw);
  // 3x3 neighbourhood: its nearest and farthest raw depths (linear depth is monotonic in both
  // projections, so two conversions give the spread around s and the minimum depth). Texels away
  // from the face's border read the buffer copy at fixed offsets, without bounds tests.
  float rawMin = raw;
  float rawMax = raw;
  if (interior && kTexelBuffer) {
    int centre = (int(face) * res + t.y) * res + t.x;
    for (int y = -1; y <= 1; ++y) {
      for (int x = -1; x <= 1; ++x) {
        float sq = shadowTexels[centre + y * res + x];
        rawMin = min(rawMin, sq);
        rawMax = max(rawMax, sq);
      }
    }
  } else {
    for (int y = -1; y <= 1; ++y) {
      for (int x = -1; x <= 1; ++x) {
        ivec2 q = t + ivec2(x, y);
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(res)))) {
          if (kind == SHADOW_CUBE) flags |= PIP_SEAM;
          continue;
        }
        float sq = LIGHT_TEXEL(shadowMap, shadowTexels, q, face, res);
        rawMin = min(rawMin, sq);
        rawMax = max(rawMax, sq);
      }
    }
  }
  float zMin = linearDepth(rawMin);
  // Contact: the map does not put the receiver behind its texel's surface, yet another surface
  // meets the receiver there - a leaf through a leaf, a wall rising from a floor, a step's foot -
  // and may shadow it within the bias: a neighbour nearer to the light than the receiver's depth
  // interval reaches (1.5 intervals: a neighbour's centre is at most 2.1 texels away), cheap, for
  // tall rises; layerOver, for layers of any height above the test's resolution.
  bool contact = s >= lo && zMin < d - 1.5 * (d - min(dHat, d));
  float zMax = linearDepth(rawMax);
  float delta = max(zMax - s, s - zMin);

  bool overlaps = hi >= s - delta && lo <= s + delta;
  bool straddles = dHat < s && d > s;
  if ((overlaps || straddles) && delta > push.deltaThreshold) flags |= PIP_EDGE;
  if (contact) flags |= PIP_CONTACT;
  if (area) {
    // Outside the penumbra mask the centre map's lit/umbra answer stands for every light sample,
    // so what makes that answer doubtful for the centre (above) puts a pixel in the mask too. The
    // mask: an edge texel's splat covers the pixel, or another surface lies over a lit receiver
    // within the bias (its penumbra is narrower than a texel), or the umbra's blocker lies within
    // the receiver's own depth interval (it may be the receiver itself: acne), or part of the
    // light is below the receiver's tangent plane or its face's plane.
    flags &= ~PIP_SEAM;  // the windows handle seams
    // Explained, every rule that holds is named; else the first ends the search.
    uint rules = ((flags & PIP_EDGE) != 0u ? PIP_MASK_EDGE_DOUBT : 0u) |
                 ((flags & PIP_THIN) != 0u ? PIP_MASK_THIN_DOUBT : 0u) |
                 ((flags & PIP_CONTACT) != 0u ? PIP_MASK_CONTACT_DOUBT : 0u);
    if (facing < halfExtent || dot(nf, light.position.xyz - p) < halfExtent) rules |= PIP_MASK_TANGENT;
    if (vis == 0.0 && s >= lo) rules |= PIP_MASK_OWN_DEPTH;
    if (rules == 0u || kExplain) {
      rules |= blockerWithinReach(p, offsetP, nf, texel, face, vis > 0.0, interior, t, halfExtent, kExplain, tileClear);
    }
    if (kExplain) why[index] = rules;
    return write(index, vis, rules != 0u ? flags | PIP_PENUMBRA : flags, 0.0, rayEnd);
  }
  if (vis == 0.0 && s >= lo && flags == 0u) flags |= PIP_ACNE;
  if (s >= lo && flags == 0u && interior &&
      layerOver(p, nf, texel, viewProj, face, t)) flags |= PIP_CONTACT;
  if (vis == 0.0 && flags == 0u && gapBetweenBlockers(p, viewProj, face)) flags |= PIP_GAP;
  zMin = min(zMin, thinDepth);
  if (kExplain) {
    uint reason = PIP_WHY_NONE;
    if (flags == 0u) {
      if (overlaps) reason = PIP_WHY_BIAS;
      else if (delta > push.deltaThreshold) reason = PIP_WHY_INTERVAL;
      else if (delta > push.depthMargin) reason = PIP_WHY_DELTA;
      else reason = PIP_WHY_FLAT;
    }
    why[index] = reason;
  }

  float maxDistance = 0.0;
  if (flags != 0u && push.useIntervals != 0u) {
    vec3 origin = shadowRayOrigin(light, p, n);
    vec3 dir = directionToLight(light, origin, light.position.xyz);
    float limit = zMin - (zMax - zMin) - 2.0 * texel;
    float rate = axisDepthRate(viewProj * vec4(dir, 0.0));  // < 0: towards the light
    float start = axisDepth(viewProj * vec4(origin, 1.0));
    if (rate < 0.0) maxDistance = max((limit - start) / rate, 2.0 * light.rayEpsilon);
  }
  return write(index, vis, flags, maxDistance, rayEnd);
}

#include "pip_tiles.glsl"

void main() {
  if (kTilePass) {
    uvec2 tile = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(tile * PIP_MASK_TILE_SIZE, uvec2(frame.width, frame.height)))) return;
    uint index = tileIndex(tile);
    maskTiles[index] = traceWhole(index) ? PIP_TILE_TRACE : maskTile(tile);
    return;
  }
  ivec2 pix = ivec2(gl_GlobalInvocationID.xy);
  uint index = uint(pix.y) * frame.width + uint(pix.x);
  bool inside = pix.x < int(frame.width) && pix.y < int(frame.height);
  // beyond the light's range (its rectangle) nothing is lit: 0, unflagged, as for the sky but dark
  bool inRect = inLightRect(frame.lightRectMin, frame.lightRectMax, uint(pix.x), uint(pix.y));
  vec4 position = inside && inRect ? imageLoad(gPosition, pix) : vec4(0.0);
  vec3 n = vec3(0.0);
  float rayEnd = 0.0;
  uint flags = 0u;
  uint tile = tileIndex(uvec2(pix) / PIP_MASK_TILE_SIZE);
  bool wholeTile = inside && traceWhole(tile);
  if (position.w != 0.0) {
    n = imageLoad(gNormal, pix).xyz;
    bool tileClear = push.tileTest != 0u && maskTiles[tile] == PIP_TILE_CLEAR;
    // The face normal (layerOver's plane) is loaded here with the others: under layerOver's
    // divergent condition lavapipe paid ~1.3 ms more for the same load at 1024^2.
    flags = classify(index, pix, position.xyz, n, faceNormalAt(pix), tileClear, wholeTile, rayEnd);
  } else if (inside && push.cornerUnion == 0u) {
    visibility[index] = inRect ? 1.0 : 0.0;
    traceFlags[index] = 0u;
  }
  if (push.tileTraceBelow != 0u && inside) countTile(tile, uvec2(pix), position.w != 0.0, flags != 0u, wholeTile);
  if (push.appendList == 0u) return;  // uniform: the compaction pass makes the list

  // The flagged pixels go straight into the trace list: one atomic on the list's count per
  // subgroup (a run of neighbouring pixels), then each flagged lane writes its point.
  uint flagged = flags != 0u ? 1u : 0u;
  uint slot = subgroupExclusiveAdd(flagged);
  uint total = subgroupAdd(flagged);
  uint first = 0u;
  if (total != 0u && subgroupElect()) {
    first = atomicAdd(traceCount.count, total);
    atomicMax(traceCount.groupsX, (first + total + TRACE_GROUP_SIZE - 1u) / TRACE_GROUP_SIZE);
  }
  first = subgroupMax(first);  // the elected lane's, the others hold 0
  if (flagged == 0u || first + slot >= frame.traceCapacity) return;  // the host refuses an overfull list
  // Member by member: the padding is not written (on lavapipe each word is a scatter).
  pointList[first + slot].position = position.xyz;
  pointList[first + slot].pixel = index;
  pointList[first + slot].normal = n;
  pointList[first + slot].spp = frame.spp;
  pointList[first + slot].rayMax = rayEnd;
}
