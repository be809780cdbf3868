#version 450
// Shadow-map lookup for the sm and pcf methods: visibility of the light's centre per pixel.
#extension GL_GOOGLE_include_directive : require
#include "shared/frame.h"
#include "shared/raster.h"
layout(local_size_x = LOOKUP_GROUP_SIZE, local_size_y = LOOKUP_GROUP_SIZE) in;
layout(binding = 0, rgba32f) uniform readonly image2D gPosition;
layout(binding = 1, rgba32f) uniform readonly image2D gNormal;
layout(binding = 2) uniform sampler2DArray shadowMap;
layout(std430, binding = 3) readonly buffer Frame { FrameData frame; };
layout(std430, binding = 4) writeonly buffer Visibility { float visibility[]; };

const vec2 kPoisson[16] = vec2[](
    vec2(-0.94201624, -0.39906216), vec2(0.94558609, -0.76890725), vec2(-0.09418410, -0.92938870),
    vec2(0.34495938, 0.29387760), vec2(-0.91588581, 0.45771432), vec2(-0.81544232, -0.87912464),
    vec2(-0.38277543, 0.27676845), vec2(0.97484398, 0.75648379), vec2(0.44323325, -0.97511554),
    vec2(0.53742981, -0.47373420), vec2(-0.26496911, -0.41893023), vec2(0.79197514, 0.19090188),
    vec2(-0.24188840, 0.99706507), vec2(-0.81409955, 0.91437590), vec2(0.19984126, 0.78641367),
    vec2(0.14383161, -0.14100790));

// 1 if the receiver at depth `depth` is in front of the occluder stored at texel `t` of `face`.
float litAt(ivec2 t, uint face, float depth) {
  int res = int(frame.shadow.resolution);
  t = clamp(t, ivec2(0), ivec2(res - 1));
  return depth <= texelFetch(shadowMap, ivec3(t, int(face)), 0).r ? 1.0 : 0.0;
}

void main() {
  ivec2 pix = ivec2(gl_GlobalInvocationID.xy);
  if (pix.x >= int(frame.width) || pix.y >= int(frame.height)) return;
  uint index = uint(pix.y) * frame.width + uint(pix.x);
  vec4 position = imageLoad(gPosition, pix);
  if (position.w == 0.0) { visibility[index] = 1.0; return; }
  vec3 p = position.xyz;
  vec3 n = imageLoad(gNormal, pix).xyz;
  if (!lightReaches(frame.light, p, n, frame.light.position.xyz)) { visibility[index] = 0.0; return; }

  uint kind = frame.shadow.kind;
  uint face = shadowFace(kind, frame.shadow.lightPosition, p);
  float texel = shadowTexelWorld(kind, frame.shadow.texelWorld, frame.shadow.lightPosition, p);
  vec3 offsetP = p + n * (frame.shadow.normalOffset * texel);
  vec4 clip = frame.shadow.viewProj[face] * vec4(offsetP, 1.0);
  vec3 ndc = clip.xyz / clip.w;
  vec2 uv = ndc.xy * 0.5 + 0.5;
  // Outside the map (or beyond its far plane) nothing was rendered that could block.
  if (clip.w <= 0.0 || any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))) || ndc.z > 1.0) {
    visibility[index] = 1.0;
    return;
  }
  ivec2 t = ivec2(floor(uv * float(frame.shadow.resolution)));
  float lit = 0.0;
  if (frame.shadowFilter == FILTER_NONE) {
    lit = litAt(t, face, ndc.z);
  } else if (frame.shadowFilter == FILTER_POISSON) {
    float angle = 6.2831853 * hashToUnit(pcgHash(index));
    mat2 rot = mat2(cos(angle), sin(angle), -sin(angle), cos(angle));
    vec2 centre = uv * float(frame.shadow.resolution);
    for (int i = 0; i < 16; ++i) lit += litAt(ivec2(floor(centre + 2.5 * (rot * kPoisson[i]))), face, ndc.z);
    lit /= 16.0;
  } else {
    int r = frame.shadowFilter == FILTER_PCF3 ? 1 : 2;
    for (int y = -r; y <= r; ++y)
      for (int x = -r; x <= r; ++x) lit += litAt(t + ivec2(x, y), face, ndc.z);
    lit /= float((2 * r + 1) * (2 * r + 1));
  }
  visibility[index] = lit;
}
