// Per-frame data shared by the raster, lookup and shading passes (one storage buffer).
#ifndef PENUMBRA_SHARED_FRAME_H
#define PENUMBRA_SHARED_FRAME_H
#include "shared/glsl_cpp.h"
#include "shared/light.h"
PN_BEGIN

#define SHADOW_MAX_FACES 6
#define SHADOW_ORTHO 0u        // directional light: one orthographic face
#define SHADOW_PERSPECTIVE 1u  // light outside the scene (or a spot): one perspective face
#define SHADOW_CUBE 2u         // light inside the scene: six 90-degree faces (+X,-X,+Y,-Y,+Z,-Z)

#define FILTER_NONE 0u     // one texel: plain shadow mapping
#define FILTER_PCF3 1u     // 3x3 percentage-closer filtering
#define FILTER_PCF5 2u     // 5x5
#define FILTER_POISSON 3u  // 16-tap Poisson disc, rotated per pixel
#define FILTER_PCSS 4u     // percentage-closer soft shadows: blocker search, then PCF sized to the penumbra

// std430, 448 bytes.
struct ShadowMapInfo {
  mat4 viewProj[SHADOW_MAX_FACES];
  vec4 lightPosition;  // xyz: projection centre of the perspective/cube faces
  uint kind;           // SHADOW_ORTHO / SHADOW_PERSPECTIVE / SHADOW_CUBE
  uint faceCount;
  uint resolution;     // texels per side of each face
  float texelWorld;    // ortho: world size of one texel; perspective/cube: size at unit distance
  float normalOffset;  // receiver offset along its normal, in texels
  float nearPlane;     // of every face: NDC depth 0 ..
  float farPlane;      // .. NDC depth 1 (linear for ortho, perspective otherwise)
  float slopeBias;     // the maps' slope-scaled depth bias factor (0 by default: the normal offset keeps acne away)
  uint pad0, pad1, pad2, pad3;
};

// std430.
struct FrameData {
  GpuLight light;
  ShadowMapInfo shadow;
  vec4 cameraPosition;  // xyz
  uint width;
  uint height;
  uint spp;
  uint shadowFilter;  // FILTER_* for the lookup pass
  uint traceInPlace;  // 1: trace kernels take every covered pixel from the G-buffer, not the compacted list
  uint traceCapacity;  // points the trace list holds
  uvec2 tracePoints;   // the trace list's device address (low, high): shaders/point_list.glsl
  uvec2 blockers;      // where the trace writes each traced pixel's mean blocker distance (float per pixel); 0: nowhere
  // The pixels [lightRectMin, lightRectMax) the light's range projects to: beyond it the light
  // reaches no pixel, so the per-pixel passes (lookup, classification, in-place trace) answer 0
  // there without reading the G-buffer. lightRectMax (0, 0): the whole image.
  uvec2 lightRectMin;
  uvec2 lightRectMax;
  // A trace of a batch of lights (frames of several lights, hybrid/shade_pass.h; trace_points.glsl):
  // the batch's ShadeLight list and its SHADE_TILE tile lists, by address. The trace takes every
  // pixel of the light rectangle above in place (a whole number of tiles from a tile's corner) and
  // traces it to each light its tile lists that the batch traces, into the batch's visibility.
  // (0, 0): FrameData's light alone.
  uvec2 traceLights;
  uvec2 traceTiles;
  uint traceTilesX;  // tiles per row of the lists
  float lightError;  // --light-error: where shadowWeight is below it, a pixel may keep an approximate answer; 0: none
  uint pad1, pad2;
};

PN_FN bool inLightRect(uvec2 lo, uvec2 hi, uint x, uint y) {
  if (hi.x == 0u && hi.y == 0u) return true;
  return x >= lo.x && y >= lo.y && x < hi.x && y < hi.y;
}

// The cube face a world point falls in, seen from the light (major axis of p - light).
// Helpers take single fields: copying the whole ShadowMapInfo per invocation is slow on lavapipe.
PN_FN uint shadowFace(uint kind, vec4 lightPosition, vec3 p) {
  if (kind != SHADOW_CUBE) return 0u;
  vec3 d = p - vec3(lightPosition);
  vec3 a = abs(d);
  if (a.x >= a.y && a.x >= a.z) return d.x >= 0.0f ? 0u : 1u;
  if (a.y >= a.z) return d.y >= 0.0f ? 2u : 3u;
  return d.z >= 0.0f ? 4u : 5u;
}

// Distance along the face's axis from the light (ortho: from the near plane's eye) of NDC depth z.
PN_FN float linearShadowDepth(uint kind, float nearPlane, float farPlane, float z) {
  if (kind == SHADOW_ORTHO) return nearPlane + z * (farPlane - nearPlane);
  return nearPlane * farPlane / (farPlane - z * (farPlane - nearPlane));
}
// Its inverse: the NDC depth of distance w along the face's axis.
PN_FN float rawShadowDepth(uint kind, float nearPlane, float farPlane, float w) {
  if (kind == SHADOW_ORTHO) return (w - nearPlane) / (farPlane - nearPlane);
  return (farPlane - nearPlane * farPlane / w) / (farPlane - nearPlane);
}

// World size of one shadow-map texel at p.
PN_FN float shadowTexelWorld(uint kind, float texelWorld, vec4 lightPosition, vec3 p) {
  if (kind == SHADOW_ORTHO) return texelWorld;
  return texelWorld * length(p - vec3(lightPosition));
}

PN_END
#endif
