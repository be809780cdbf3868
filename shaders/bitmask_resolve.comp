#version 450
// Bitmask visibility sampling, resolve: a covered pixel on the receiver (onReceiver) takes its visibility from its
// texel's hidden-samples bits: the fraction of the shared pattern's samples not hidden that are
// above its tangent plane (lightReaches, as the tracers count them). Every other covered pixel is
// flagged for the fallback tracer (the compaction lists it); uncovered ones are lit.
#extension GL_GOOGLE_include_directive : require
#include "shared/bitmask.h"
#include "shared/frame.h"
layout(local_size_x = BITMASK_GROUP_SIZE, local_size_y = BITMASK_GROUP_SIZE) in;
layout(binding = 0, rgba32f) uniform readonly image2D gPosition;
layout(binding = 1, rgba32f) uniform readonly image2D gNormal;
layout(std430, binding = 2) readonly buffer Frame { FrameData frame; };
layout(std430, binding = 3) readonly buffer Bitmask { BitmaskFrame bitmask; };
layout(std430, binding = 4) readonly buffer Hidden { uint hidden[]; };
layout(std430, binding = 5) writeonly buffer Visibility { float visibility[]; };
layout(std430, binding = 6) writeonly buffer TraceFlags { uint traceFlags[]; };

void main() {
  ivec2 pix = ivec2(gl_GlobalInvocationID.xy);
  if (pix.x >= int(frame.width) || pix.y >= int(frame.height)) return;
  uint index = uint(pix.y) * frame.width + uint(pix.x);
  vec4 position = imageLoad(gPosition, pix);
  if (position.w == 0.0) {
    visibility[index] = 1.0;
    traceFlags[index] = 0u;
    return;
  }
  vec3 p = position.xyz, n = imageLoad(gNormal, pix).xyz;
  vec2 uv = receiverUv(bitmask, p);
  if (!onReceiver(bitmask, p, n, uv)) {
    visibility[index] = 1.0;
    traceFlags[index] = 1u;  // the fallback traces it
    return;
  }
  uint res = bitmask.resolution, words = bitmask.words;
  uvec2 texel = min(uvec2(uv * float(res)), uvec2(res - 1u));
  uint at = (texel.y * res + texel.x) * words;
  uint spp = frame.spp, seen = 0u;
  for (uint s = 0u; s < spp; ++s) {
    bool hiddenSample = ((hidden[at + s / 32u] >> (s % 32u)) & 1u) != 0u;
    if (!hiddenSample && lightReaches(frame.light, p, n, lightSamplePoint(frame.light, index, s, spp))) ++seen;
  }
  visibility[index] = float(seen) / float(spp);
  traceFlags[index] = 0u;
}
