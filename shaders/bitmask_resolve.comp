#version 450
// Bitmask visibility sampling, resolve: a covered pixel on the receiver (onReceiver) takes its
// visibility from the hidden-samples bits of the texels around it: the fraction of the shared
// pattern's samples not hidden that are above its tangent plane (lightReaches, as the tracers count
// them). Every other covered pixel is flagged for the fallback tracer (the compaction lists it) and
// uncovered ones are lit, or, after srt's classification (keepOthers), both keep its answer.
#extension GL_GOOGLE_include_directive : require
#include "shared/bitmask.h"
#include "shared/frame.h"
layout(local_size_x = BITMASK_GROUP_SIZE, local_size_y = BITMASK_GROUP_SIZE) in;
layout(binding = BITMASK_RESOLVE_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(binding = BITMASK_RESOLVE_BINDING_NORMAL, rgba32f) uniform readonly image2D gNormal;
layout(std430, binding = BITMASK_RESOLVE_BINDING_FRAME_DATA) readonly buffer Frame { FrameData frame; };
layout(std430, binding = BITMASK_RESOLVE_BINDING_FRAME) readonly buffer Bitmask { BitmaskFrame bitmask; };
layout(std430, binding = BITMASK_RESOLVE_BINDING_HIDDEN) readonly buffer Hidden { uint hidden[]; };
layout(std430, binding = BITMASK_RESOLVE_BINDING_VISIBILITY) writeonly buffer Visibility { float visibility[]; };
layout(std430, binding = BITMASK_RESOLVE_BINDING_TRACE_FLAGS) writeonly buffer TraceFlags { uint traceFlags[]; };
layout(std430, binding = BITMASK_RESOLVE_BINDING_HEIGHTS) readonly buffer Heights { float heights[]; };  // a height field's, per texel

// A height field's surface height at map point uv (bilinear between texel centres), and how much
// it varies there (the on-receiver test's allowance for the facets between the centres).
vec2 fieldHeight(vec2 uv) {
  if (bitmask.field.x == 0.0) return vec2(0.0);
  int res = int(bitmask.resolution);
  vec2 at = uv * float(res) - 0.5;
  ivec2 t0 = ivec2(floor(at));
  vec2 f = at - vec2(t0);
  float h = 0.0, lo = 1e30, hi = -1e30;
  for (int c = 0; c < 4; ++c) {
    ivec2 t = clamp(t0 + ivec2(c & 1, c >> 1), ivec2(0), ivec2(res - 1));
    float v = heights[t.y * res + t.x];
    h += ((c & 1) != 0 ? f.x : 1.0 - f.x) * ((c & 2) != 0 ? f.y : 1.0 - f.y) * v;
    lo = min(lo, v);
    hi = max(hi, v);
  }
  return vec2(h, hi - lo);
}

void main() {
  ivec2 pix = ivec2(gl_GlobalInvocationID.xy);
  if (pix.x >= int(frame.width) || pix.y >= int(frame.height)) return;
  uint index = uint(pix.y) * frame.width + uint(pix.x);
  vec4 position = imageLoad(gPosition, pix);
  bool keep = bitmask.keepOthers != 0u;  // srt's classification answered them (lit, umbra or flagged)
  if (position.w == 0.0) {
    if (!keep) {
      visibility[index] = 1.0;
      traceFlags[index] = 0u;
    }
    return;
  }
  vec3 p = position.xyz, n = imageLoad(gNormal, pix).xyz;
  vec2 uv = receiverUv(bitmask, p);
  vec2 field = fieldHeight(uv);
  if (!onReceiver(bitmask, p, n, uv, field.x, field.y)) {
    if (!keep) {
      visibility[index] = 1.0;
      traceFlags[index] = 1u;  // frt traces it
    }
    return;
  }
  // The samples above p's tangent plane (under each texel's symmetry), then the unhidden ones among
  // them at the four texel centres around p, interpolated bilinearly: each texel's count is exact for its centre, and
  // between centres a penumbra varies smoothly (courtyard at 512^2, light 0.1, 64 samples, a 512^2
  // map: 4.1% of the pixels off by more than 0.05 from the reference with the nearest texel, 1.5%
  // bilinear; a 2048^2 map: 0.50%, 0.10%).
  uint res = bitmask.resolution, words = bitmask.words, spp = frame.spp;
  vec2 at = uv * float(res) - 0.5;
  ivec2 t0 = ivec2(floor(at));
  vec2 f = at - vec2(t0);
  // Most receivers see the whole light above their tangent plane: every sample counts, under any
  // texel's symmetry (the light's bounding square's corners all reach p).
  bool wholeLight = true;
  for (int c = 0; c < 4; ++c) wholeLight = wholeLight && lightReaches(frame.light, p, n, lightSquareCorner(bitmask, c));
  vec3 lt = bitmask.lightT.xyz, lb = bitmask.lightB.xyz, centre = bitmask.lightCentre.xyz;
  float seen = 0.0;
  for (int c = 0; c < 4; ++c) {
    ivec2 t = clamp(t0 + ivec2(c & 1, c >> 1), ivec2(0), ivec2(int(res) - 1));
    float weight = ((c & 1) != 0 ? f.x : 1.0 - f.x) * ((c & 2) != 0 ? f.y : 1.0 - f.y);
    if (weight == 0.0) continue;
    uint texel = uint(t.y) * res + uint(t.x), symmetry = texelSymmetry(bitmask, texel);
    for (uint w = 0u; w < words; ++w) {
      uint reach = spp >= w * 32u + 32u ? ~0u : (1u << (spp - w * 32u)) - 1u;  // the word's samples
      for (uint k = 0u; !wholeLight && k < 32u && w * 32u + k < spp; ++k) {
        vec2 q = applySymmetry(symmetry, lightSampleOnLight(frame.light, index, w * 32u + k, spp));
        if (!lightReaches(frame.light, p, n, centre + frame.light.size * (q.x * lt + q.y * lb))) reach &= ~(1u << k);
      }
      seen += weight * float(bitCount(~hidden[texel * words + w] & reach));
    }
  }
  visibility[index] = seen / float(spp);
  traceFlags[index] = 0u;
}
