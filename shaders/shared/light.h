// The light as every pass and the reference see it, and its per-pixel stratified samples.
// Samples depend only on (pixel, sample index, spp), so every method and the Embree reference
// trace the same light points and their differences are method error, not noise.
#ifndef PENUMBRA_SHARED_LIGHT_H
#define PENUMBRA_SHARED_LIGHT_H
#include "shared/glsl_cpp.h"
PN_BEGIN

#define LIGHT_DIRECTIONAL 0u
#define LIGHT_SPOT 1u
#define LIGHT_POINT 2u
#define LIGHT_RECT 3u
#define LIGHT_DISK 4u

// std430, 96 bytes.
struct GpuLight {
  vec4 position;   // xyz world position (unused by directional)
  vec4 direction;  // xyz unit: where the light points (travel direction for directional)
  vec4 tangent;    // xyz unit, orthogonal to direction: first edge of a rect, any axis of a disk
  vec4 color;      // rgb: colour times intensity (Light::intensity); w: 1 = inverse-square falloff
  uint type;
  float size;          // rect side / disk diameter in world units; 0 = point
  float cosHalfAngle;  // spot cone; -1 for other lights
  float rayEpsilon;    // smallest shadow-ray origin offset along the normal, world units (shadowRayOrigin)
  uint sampleFrame;    // frame of a sequence: rotates every pixel's samples (lightSampleOffset); 0 = unrotated
  uint sharedPattern;  // 1: every pixel uses the same samples (those of SHARED_PATTERN_SEED: method bitmask's)
  float range;         // > 0: the contribution ends at this distance (glTF's window)
  float cosInnerHalfAngle;  // spot: full strength inside this cone, fading to cosHalfAngle's
};

// The seed of the one pattern every pixel uses when GpuLight::sharedPattern is set: method bitmask
// looks its samples up in a table, so it cannot use a pattern per pixel; the reference and the
// tracers use this one too when asked (--shared-samples), so that comparisons measure the method.
#define SHARED_PATTERN_SEED 0x5eedu

PN_FN uint pcgHash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// Exact on CPU and GPU: 24 random bits scaled by 2^-24.
PN_FN float hashToUnit(uint h) { return float(h >> 8u) * (1.0f / 16777216.0f); }

// Sample `s` of `spp` for `pixel`: jittered on a ceil(sqrt(spp)) grid, jitter seeded by the pixel.
PN_FN vec2 stratifiedSample(uint pixel, uint s, uint spp) {
  uint nx = uint(ceil(sqrt(float(spp))));
  uint ny = (spp + nx - 1u) / nx;
  uint h = pcgHash(pixel * 9781u + pcgHash(s + 0x9e3779b9u));
  float jx = hashToUnit(h);
  float jy = hashToUnit(pcgHash(h));
  return vec2((float(s % nx) + jx) / float(nx), (float(s / nx) + jy) / float(ny));
}

PN_FN bool isAreaLight(GpuLight light) {
  return (light.type == LIGHT_RECT || light.type == LIGHT_DISK) && light.size > 0.0f;
}

// Frame `frame`'s toroidal shift of every pixel's sample pattern: the R2 low-discrepancy sequence
// (Roberts 2018) in 32-bit fixed point, exact on CPU and GPU; frame 0 shifts nothing. A pixel's
// samples stay stratified within a frame and, added over frames, fill the light evenly; the
// per-pixel jitter keeps neighbours decorrelated.
PN_FN vec2 lightSampleOffset(uint frame) {
  return vec2(hashToUnit(frame * 3242174889u), hashToUnit(frame * 2447445414u));
}

// Where sample `s` of `spp` for `pixel` lies on an area light, in units of its size from its
// centre along (tangent, cross(direction, tangent)): in [-1/2, 1/2]^2, in the light's sampleFrame.
PN_FN vec2 lightSampleOnLight(GpuLight light, uint pixel, uint s, uint spp) {
  vec2 u = stratifiedSample(light.sharedPattern != 0u ? SHARED_PATTERN_SEED : pixel, s, spp) +
           lightSampleOffset(light.sampleFrame);
  if (u.x >= 1.0f) u.x -= 1.0f;
  if (u.y >= 1.0f) u.y -= 1.0f;
  if (light.type == LIGHT_RECT) return u - 0.5f;
  // Disk: Shirley–Chiu concentric mapping keeps the strata compact.
  float a = 2.0f * u.x - 1.0f;
  float c = 2.0f * u.y - 1.0f;
  float r = 0.0f;
  float phi = 0.0f;
  if (a * a > c * c) {
    r = a;
    phi = 0.78539816f * (c / a);
  } else if (c != 0.0f) {
    r = c;
    phi = 1.57079633f - 0.78539816f * (a / c);
  }
  return (0.5f * r) * vec2(cos(phi), sin(phi));
}

// The light point that sample `s` of `spp` for `pixel` aims at (the centre for non-area lights).
PN_FN vec3 lightSamplePoint(GpuLight light, uint pixel, uint s, uint spp) {
  vec3 centre = vec3(light.position);
  if (!isAreaLight(light)) return centre;
  vec2 q = lightSampleOnLight(light, pixel, s, spp);
  vec3 t = vec3(light.tangent);
  vec3 b = cross(vec3(light.direction), t);
  return centre + light.size * (q.x * t + q.y * b);
}

// Unit direction from p towards the light point q (towards the light for directional).
PN_FN vec3 directionToLight(GpuLight light, vec3 p, vec3 q) {
  if (light.type == LIGHT_DIRECTIONAL) return -vec3(light.direction);
  return normalize(q - p);
}

// Whether light from q can reach p at all, before occlusion: p's surface (normal n) faces q,
// p is within the light's range, inside a spot's cone and in front of a rect/disk. Every method
// applies this same rule.
PN_FN bool lightReaches(GpuLight light, vec3 p, vec3 n, vec3 q) {
  vec3 l = directionToLight(light, p, q);
  if (dot(n, l) <= 0.0f) return false;
  if (light.range > 0.0f && light.type != LIGHT_DIRECTIONAL) {
    vec3 v = p - vec3(light.position);
    if (dot(v, v) >= light.range * light.range) return false;
  }
  if (light.type == LIGHT_SPOT) return dot(-l, vec3(light.direction)) >= light.cosHalfAngle;
  if (light.type == LIGHT_RECT || light.type == LIGHT_DISK) {
    return dot(p - vec3(light.position), vec3(light.direction)) > 0.0f;
  }
  return true;
}

// How much of the light's colour reaches p before occlusion and the cosine (KHR_lights_punctual's
// falloff): 1 for lights that do not fall off, so that their frames are unchanged by it.
PN_FN float lightFalloff(GpuLight light, vec3 p, vec3 l) {
  if (light.type == LIGHT_DIRECTIONAL) return 1.0f;
  float w = 1.0f;
  vec3 v = p - vec3(light.position);
  float d2 = dot(v, v);
  if (light.color.w != 0.0f) w = 1.0f / max(d2, 1e-12f);
  if (light.range > 0.0f) {
    float x = d2 / (light.range * light.range);
    w *= clamp(1.0f - x * x, 0.0f, 1.0f);
  }
  if (light.type == LIGHT_SPOT && light.cosInnerHalfAngle > light.cosHalfAngle) {
    w *= smoothstep(light.cosHalfAngle, light.cosInnerHalfAngle, dot(-l, vec3(light.direction)));
  }
  return w;
}

// The shading pass's ambient share of the albedo (shade.comp): the lights' direct sum scales the rest.
#define SHADE_AMBIENT 0.12f

// The most the light's visibility at p (G-buffer normal n) can change p's shaded value, in linear
// units per colour channel: the shading pass's direct term of the light, unshadowed, for the largest
// channel of its colour and an albedo of 1. Where it is below FrameData::lightError (--light-error)
// a method may keep an approximate answer (the map's, or unshadowed by the rule: lightReaches) and
// the image errs there by less than that.
PN_FN float shadowWeight(GpuLight light, vec3 p, vec3 n) {
  vec3 l = directionToLight(light, p, vec3(light.position));
  float colour = max(max(light.color.x, light.color.y), light.color.z);
  return (1.0f - SHADE_AMBIENT) * colour * max(dot(n, l), 0.0f) * lightFalloff(light, p, l);
}

// Corner i (0..3) of a rect light; for a disk the rim points on its two axes. The maps from these
// points (--penumbra-maps 5) see edges the centre's map may hide.
PN_FN vec3 lightCorner(GpuLight light, uint i) {
  vec3 t = vec3(light.tangent);
  vec3 b = cross(vec3(light.direction), t);
  float h = 0.5f * light.size;
  if (light.type == LIGHT_RECT) {
    return vec3(light.position) + h * ((i & 1u) != 0u ? t : -t) + h * ((i & 2u) != 0u ? b : -b);
  }
  vec3 axis = (i & 1u) != 0u ? b : t;
  return vec3(light.position) + ((i & 2u) != 0u ? h : -h) * axis;
}

// Where the shadow rays of surface point p (unit normal n, facing the viewer) start: off the
// surface along n by the scene's tolerance (light.rayEpsilon: a surface nearer than that, such as
// a decal, is part of the receiver and does not shadow it) or by the position's own float error
// (SHADOW_RAY_ULPS units in the last place of its largest coordinate), whichever is larger, so that
// a scene far from the origin does not shadow itself. Every tracer and the reference use this.
#define SHADOW_RAY_ULPS 4.0f
PN_FN vec3 shadowRayOrigin(GpuLight light, vec3 p, vec3 n) {
  float magnitude = max(max(abs(p.x), abs(p.y)), abs(p.z));
  return p + n * max(light.rayEpsilon, magnitude * (SHADOW_RAY_ULPS / 8388608.0f));
}

// Number of light samples a shading point uses: spp for area lights, one otherwise.
PN_FN uint lightSampleCount(GpuLight light, uint spp) { return isAreaLight(light) ? max(spp, 1u) : 1u; }

PN_END
#endif
