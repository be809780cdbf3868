// Indirect rays from the camera's G-buffer (Keul et al. 2018's use of the line space): K
// cosine-weighted rays per covered pixel, seeded per pixel like every sampling in Penumbra, for
// ambient occlusion (`ao`: the fraction of rays that leave within a radius) and one-bounce diffuse
// light (`indirect`: at each ray's closest hit, the light's centre seen through one shadow ray,
// reflected by the hit's base colour). The GPU kernels (indirect_trace.glsl) and the Embree
// reference (EmbreeTracer::traceIndirect, raytrace/embree_tracer.cpp) sample and shade with these same functions.
#ifndef PENUMBRA_SHARED_INDIRECT_H
#define PENUMBRA_SHARED_INDIRECT_H
#include "shared/glsl_cpp.h"
#include "shared/gbuffer.h"
#include "shared/light.h"
#include "shared/scene_triangles.h"
#include "shared/shading_point.h"
#ifdef __cplusplus
#include <glm/gtc/packing.hpp>
#endif
PN_BEGIN

#define INDIRECT_AO 0u        // output: the fraction of rays without a hit within aoRadius
#define INDIRECT_BOUNCE 1u    // output: one-bounce diffuse light (rgb)
#define INDIRECT_GROUP_SIZE 8 // 8 x 8 pixels per workgroup
#define INDIRECT_MAX_RAYS 1024u
#define INDIRECT_SEED 0x1d1ec7u
#define INDIRECT_HIT_SHADOW_RAY 0u  // a bounce's hit sees the light through one shadow ray (exact)
#define INDIRECT_HIT_SHADOW_MAP 1u  // ... through the light's shadow map (sm's answer: no ray)  // salts the pixel seed so rays do not repeat the light samples' pattern

// Kernel bindings (after them the tracer's own: shared/bvh.h, shared/linespace.h, ...).
#define INDIRECT_BINDING_POSITION 20
#define INDIRECT_BINDING_NORMAL 21
#define INDIRECT_BINDING_FRAME 22
#define INDIRECT_BINDING_OUTPUT 24     // vec4 per pixel: rgb indirect light, a occlusion (1 - ao)
#define INDIRECT_BINDING_COUNTERS 25   // INDIRECT_COUNTER_WORDS uint
#define INDIRECT_BINDING_SHADOW_MAP 26     // the light's map (sampler2DArray) ...
#define INDIRECT_BINDING_SHADOW_TEXELS 27  // ... and its texel copy (light_texels.glsl)

// 64-bit counters as (low, high) 32-bit words.
#define INDIRECT_COUNTER_RAYS 0u         // indirect rays
#define INDIRECT_COUNTER_SHADOW_RAYS 2u  // shadow rays from their hits
#define INDIRECT_COUNTER_NODE_VISITS 4u
#define INDIRECT_COUNTER_TESTS 6u        // triangle (or candidate) tests
#define INDIRECT_COUNTER_WORDS 8u

// What every indirect kernel needs besides its tracer's data; its tracer's push data follows.
struct IndirectParams {
  uint mode;       // INDIRECT_AO or INDIRECT_BOUNCE
  uint rays;       // per pixel, 1..INDIRECT_MAX_RAYS
  uint frame;      // of a sequence: rotates the pattern (lightSampleOffset); 0 = unrotated
  float aoRadius;  // world units
  float rayMax;    // world units: indirect rays of `indirect` end here (past the scene)
  uint hitLight;   // INDIRECT_HIT_SHADOW_RAY or INDIRECT_HIT_SHADOW_MAP
  uvec2 triangles; // device address (low, high) of the scene's triangles (SceneTriangle[], scene order)
};

// Unit vectors t, b completing unit n to a right-handed frame (Duff et al. 2017).
PN_FN vec3 indirectTangent(vec3 n) {
  float s = n.z >= 0.0f ? 1.0f : -1.0f;
  float a = -1.0f / (s + n.z);
  return vec3(1.0f + s * n.x * n.x * a, s * n.x * n.y * a, -s * n.x);
}
PN_FN vec3 indirectBitangent(vec3 n) {
  float s = n.z >= 0.0f ? 1.0f : -1.0f;
  float a = -1.0f / (s + n.z);
  return vec3(n.x * n.y * a, s + n.y * n.y * a, -n.y);
}

// Ray k of `count` for `pixel` about the unit normal n: cosine-weighted (Malley: a stratified
// point on the unit disk lifted to the hemisphere), the strata jittered per pixel and shifted per
// frame as the light samples are.
PN_FN vec3 indirectDirection(uint pixel, uint k, uint count, uint frame, vec3 n) {
  vec2 u = stratifiedSample(pcgHash(pixel ^ INDIRECT_SEED), k, count) + lightSampleOffset(frame);
  if (u.x >= 1.0f) u.x -= 1.0f;
  if (u.y >= 1.0f) u.y -= 1.0f;
  float r = sqrt(u.x);
  float phi = 6.28318531f * u.y;
  return normalize(indirectTangent(n) * (r * cos(phi)) + indirectBitangent(n) * (r * sin(phi)) +
                   n * sqrt(max(0.0f, 1.0f - u.x)));
}

// Barycentric weights of p (on or near the triangle's plane) for v0, v1, v2; outside the triangle
// some are negative (extrapolation, for the candidate line space's plane hits).
PN_FN vec3 triangleWeights(SceneTriangle tri, vec3 p) {
  vec3 e1 = tri.v1 - tri.v0;
  vec3 e2 = tri.v2 - tri.v0;
  vec3 d = p - tri.v0;
  float d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2);
  float d1 = dot(d, e1), d2 = dot(d, e2);
  float den = d11 * d22 - d12 * d12;
  if (den <= 0.0f) return vec3(1.0f, 0.0f, 0.0f);
  float w1 = (d22 * d1 - d12 * d2) / den;
  float w2 = (d11 * d2 - d12 * d1) / den;
  return vec3(1.0f - w1 - w2, w1, w2);
}

PN_FN vec3 triangleFaceNormal(SceneTriangle tri) { return normalize(cross(tri.v1 - tri.v0, tri.v2 - tri.v0)); }

// The vertex normals interpolated (or extrapolated) with weights w, not normalized.
PN_FN vec3 triangleShadingNormal(SceneTriangle tri, vec3 w) {
  return w.x * octahedralDecode(unpackSnorm2x16(tri.normal0)) + w.y * octahedralDecode(unpackSnorm2x16(tri.normal1)) +
         w.z * octahedralDecode(unpackSnorm2x16(tri.normal2));
}

// A ray's hit as `indirect` shades it: its surface turned towards the ray (both sides of every
// triangle reflect), the shadow ray towards the light's centre, and what it reflects if that ray
// is unblocked.
struct IndirectHit {
  vec3 position;
  bool lit;          // the light reaches the surface at all (lightReaches): else no shadow ray
  vec3 shadowOrigin;
  float shadowEnd;   // tMax of the shadow ray
  vec3 toLight;      // unit
  float pad0;
  vec3 face;         // the triangle's unit normal, turned towards the ray's origin
  float pad1;
  vec3 reflected;    // rgb the hit sends back when the shadow ray is unblocked
};

PN_FN IndirectHit indirectHit(SceneTriangle tri, vec3 origin, vec3 dir, float t, GpuLight light) {
  IndirectHit h;
  h.position = origin + t * dir;
  vec3 face = triangleFaceNormal(tri);
  if (dot(face, dir) > 0.0f) face = -face;
  vec3 n = triangleShadingNormal(tri, triangleWeights(tri, h.position));
  float len = length(n);
  n = len > 0.0f ? n / len : face;
  if (dot(n, face) < 0.0f) n = -n;
  vec3 q = vec3(light.position);
  h.lit = lightReaches(light, h.position, face, q);
  h.shadowOrigin = shadowRayOrigin(light, h.position, face);
  h.toLight = directionToLight(light, h.position, q);
  h.shadowEnd = shadowRayEnd(distance(h.shadowOrigin, q), light.type == LIGHT_DIRECTIONAL, 0.0f);
  h.pad0 = h.pad1 = 0.0f;
  h.face = face;
  vec3 albedo = vec3(unpackUnorm4x8(tri.albedo));
  h.reflected = albedo * (max(dot(n, h.toLight), 0.0f) * vec3(light.color));
  return h;
}

PN_END
#endif
