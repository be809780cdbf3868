#version 450
// Shadow-map lookup: visibility per pixel from one shadow map. sm and pcf look up the light's
// centre map (unfiltered or PCF); pcss sizes its PCF kernel from a blocker search; msm runs this
// once per light-sample map in accumulate mode, adding weight * visibility. Filter taps compare
// the map with the receiver's plane at the tap (receiver-plane depth, from the face normal), not
// with the receiver's one depth: the map holds true depths (no slope-scaled bias by default), and a
// sloped receiver would otherwise shadow itself across the kernel.
#extension GL_GOOGLE_include_directive : require
#include "shared/frame.h"
#include "shared/raster.h"
layout(local_size_x = LOOKUP_GROUP_SIZE, local_size_y = LOOKUP_GROUP_SIZE) in;
layout(binding = LOOKUP_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(binding = LOOKUP_BINDING_NORMAL, rgba32f) uniform readonly image2D gNormal;
layout(binding = LOOKUP_BINDING_SHADOW_MAP) uniform sampler2DArray shadowMap;
layout(std430, binding = LOOKUP_BINDING_FRAME) readonly buffer Frame { FrameData frame; };
layout(std430, binding = LOOKUP_BINDING_VISIBILITY) buffer Visibility { float visibility[]; };
layout(std430, binding = LOOKUP_BINDING_SHADOW_TEXELS) readonly buffer ShadowTexels { float shadowTexels[]; };
layout(binding = LOOKUP_BINDING_FACE_NORMAL, r32ui) uniform readonly uimage2D gFaceNormal;
#include "light_texels.glsl"
#include "receiver_plane.glsl"
// accumulateWeight 0: overwrite visibility; > 0: add accumulateWeight * visibility (msm).
layout(push_constant) uniform Push { float accumulateWeight; } push;

// PCSS cost bounds: 16 blocker-search taps and 32 filter taps, each within this many texels of the
// receiver's texel. Larger penumbrae are under-blurred rather than made unboundedly expensive.
const float kPcssMaxRadiusTexels = 32.0;

const vec2 kPoisson[16] = vec2[](
    vec2(-0.94201624, -0.39906216), vec2(0.94558609, -0.76890725), vec2(-0.09418410, -0.92938870),
    vec2(0.34495938, 0.29387760), vec2(-0.91588581, 0.45771432), vec2(-0.81544232, -0.87912464),
    vec2(-0.38277543, 0.27676845), vec2(0.97484398, 0.75648379), vec2(0.44323325, -0.97511554),
    vec2(0.53742981, -0.47373420), vec2(-0.26496911, -0.41893023), vec2(0.79197514, 0.19090188),
    vec2(-0.24188840, 0.99706507), vec2(-0.81409955, 0.91437590), vec2(0.19984126, 0.78641367),
    vec2(0.14383161, -0.14100790));

void store(uint index, float v) {
  if (push.accumulateWeight > 0.0) visibility[index] += push.accumulateWeight * v;
  else visibility[index] = v;
}

// The receiver's plane in the map: NDC depth ndcZ at texel coordinates `at`, gradient `slope`.
struct Receiver {
  vec2 at;
  float ndcZ;
  vec2 slope;
};
float depthAt(Receiver r, ivec2 t) { return r.ndcZ + dot(r.slope, vec2(t) + 0.5 - r.at); }

// Fernando 2005 for an area light of world size frame.light.size. Depths are linear along the
// face axis; radii are in texels of the map. Returns 1 when the blocker search finds nothing.
float pcss(Receiver r, uint face, mat2 rot) {
  vec2 centre = r.at;
  float ndcZ = r.ndcZ;
  uint kind = frame.shadow.kind;
  float nearPlane = frame.shadow.nearPlane, farPlane = frame.shadow.farPlane;
  float d = linearShadowDepth(kind, nearPlane, farPlane, ndcZ);
  // Texels per world unit at linear depth z: texelWorld is the texel size at unit distance for
  // perspective faces and the fixed texel size for ortho ones.
  float perWorldNear = kind == SHADOW_ORTHO ? 1.0 / frame.shadow.texelWorld : 1.0 / (nearPlane * frame.shadow.texelWorld);
  float perWorldAtD = kind == SHADOW_ORTHO ? 1.0 / frame.shadow.texelWorld : 1.0 / (d * frame.shadow.texelWorld);
  float lightSize = frame.light.size;
  // Blockers of the receiver lie inside the cone from it to the light; on the near plane that
  // cone is lightSize * (d - near) / d wide. Searching its half-width covers it.
  float searchRadius = min(0.5 * lightSize * perWorldNear * max(d - nearPlane, 0.0) / d, kPcssMaxRadiusTexels);
  float blockerSum = 0.0;
  float blockers = 0.0;
  for (int i = 0; i < 16; ++i) {
    ivec2 t = ivec2(floor(centre + searchRadius * (rot * kPoisson[i])));
    int res = int(frame.shadow.resolution);
    t = clamp(t, ivec2(0), ivec2(res - 1));
    float z = LIGHT_TEXEL(shadowMap, shadowTexels, t, face, res);
    if (z < depthAt(r, t)) {
      blockerSum += linearShadowDepth(kind, nearPlane, farPlane, z);
      blockers += 1.0;
    }
  }
  if (blockers == 0.0) return 1.0;
  float zB = blockerSum / blockers;
  // Penumbra width at the receiver (similar triangles, parallel planes), halved to a kernel radius.
  float penumbraWorld = max(d - zB, 0.0) * lightSize / zB;
  float radius = min(0.5 * penumbraWorld * perWorldAtD, kPcssMaxRadiusTexels);
  // 32 taps: the 16-tap disc at two rotations.
  float c = cos(1.0), s = sin(1.0);
  mat2 rot2 = rot * mat2(c, s, -s, c);
  float lit = 0.0;
  for (int i = 0; i < 16; ++i) {
    ivec2 a = ivec2(floor(centre + radius * (rot * kPoisson[i])));
    ivec2 b = ivec2(floor(centre + radius * (rot2 * kPoisson[i])));
    lit += litAt(a, face, depthAt(r, a)) + litAt(b, face, depthAt(r, b));
  }
  return lit / 32.0;
}

void main() {
  // the dispatch covers the light's rectangle (the host leaves 0 beyond it)
  ivec2 pix = ivec2(gl_GlobalInvocationID.xy + frame.lightRectMin);
  if (pix.x >= int(frame.width) || pix.y >= int(frame.height)) return;
  if (!inLightRect(frame.lightRectMin, frame.lightRectMax, uint(pix.x), uint(pix.y))) return;
  uint index = uint(pix.y) * frame.width + uint(pix.x);
  vec4 position = imageLoad(gPosition, pix);
  if (position.w == 0.0) { store(index, 1.0); return; }
  vec3 p = position.xyz;
  vec3 n = imageLoad(gNormal, pix).xyz;
  if (!lightReaches(frame.light, p, n, frame.light.position.xyz)) { store(index, 0.0); return; }

  uint face;
  float texel;
  vec3 offsetP, ndc;
  vec2 uv;
  if (!shadowMapPoint(p, n, face, texel, offsetP, ndc, uv)) {
    store(index, 1.0);
    return;
  }
  ivec2 t = ivec2(floor(uv * float(frame.shadow.resolution)));
  float lit = 0.0;
  if (frame.shadowFilter == FILTER_NONE || (frame.shadowFilter == FILTER_PCSS && !isAreaLight(frame.light))) {
    lit = litAt(t, face, ndc.z);
    store(index, lit);
    return;
  }
  // A face turned from the light (seen only through the shading normal) has no plane in the map.
  Receiver r = Receiver(uv * float(frame.shadow.resolution), ndc.z, vec2(0.0));
  vec3 nf = faceNormalAt(pix);
  if (lightReaches(frame.light, p, nf, frame.light.position.xyz)) {
    r.slope = planeDepthGradient(offsetP, nf, texel, faceViewProj(face), r.at, ndc.z);
    if (any(isinf(r.slope)) || any(isnan(r.slope))) r.slope = vec2(0.0);
  }
  if (frame.shadowFilter == FILTER_PCSS) {
    float angle = 6.2831853 * hashToUnit(pcgHash(index));
    mat2 rot = mat2(cos(angle), sin(angle), -sin(angle), cos(angle));
    lit = pcss(r, face, rot);
  } else if (frame.shadowFilter == FILTER_POISSON) {
    float angle = 6.2831853 * hashToUnit(pcgHash(index));
    mat2 rot = mat2(cos(angle), sin(angle), -sin(angle), cos(angle));
    for (int i = 0; i < 16; ++i) {
      ivec2 q = ivec2(floor(r.at + 2.5 * (rot * kPoisson[i])));
      lit += litAt(q, face, depthAt(r, q));
    }
    lit /= 16.0;
  } else {
    int k = frame.shadowFilter == FILTER_PCF3 ? 1 : 2;
    for (int y = -k; y <= k; ++y) {
      for (int x = -k; x <= k; ++x) lit += litAt(t + ivec2(x, y), face, depthAt(r, t + ivec2(x, y)));
    }
    lit /= float((2 * k + 1) * (2 * k + 1));
  }
  store(index, lit);
}
