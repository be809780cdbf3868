#version 450
// Bitmask visibility sampling (Eisemann & Décoret 2007), the Hough table: for every bin of oriented
// lines through the light's normalized square, the light samples left of the bin's centre line, as
// bits (one invocation per bin and 32-bit word). The samples are the shared pattern's
// (GpuLight::sharedPattern) in this frame, the ones the reference traces with --shared-samples.
#extension GL_GOOGLE_include_directive : require
#include "shared/bitmask.h"
#include "shared/light.h"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Light { GpuLight light; };
layout(std430, binding = 1) readonly buffer Frame { BitmaskFrame frame; };
layout(std430, binding = 2) writeonly buffer Table { uint table[]; };

void main() {
  uint index = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  uint words = frame.words;
  if (index >= BITMASK_THETA_BINS * BITMASK_R_BINS * words) return;
  uint bin = index / words, word = index % words;
  vec3 line = houghBinLine(bin / BITMASK_R_BINS, bin % BITMASK_R_BINS);
  uint bits = 0u;
  for (uint k = 0u; k < 32u; ++k) {
    uint s = word * 32u + k;
    if (s >= frame.samples) break;
    vec2 q = lightSampleOnLight(light, 0u, s, frame.samples);
    if (dot(q, line.xy) > line.z) bits |= 1u << k;
  }
  table[index] = bits;
}
