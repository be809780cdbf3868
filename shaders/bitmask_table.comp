#version 450
// Bitmask visibility sampling (Eisemann & Décoret 2007), the Hough table: for every bin of oriented
// lines through the light's normalized square, the light samples left of the bin's centre line, as
// bits (one invocation per bin and 32-bit word). The samples are the shared pattern's
// (GpuLight::sharedPattern) in this frame, the ones the reference traces with --shared-samples.
#extension GL_GOOGLE_include_directive : require
#include "shared/bitmask.h"
#include "shared/light.h"
layout(local_size_x = BITMASK_TABLE_GROUP_SIZE) in;
layout(std430, binding = BITMASK_TABLE_BINDING_LIGHT) readonly buffer Light { GpuLight light; };
layout(push_constant) uniform Push { BitmaskTablePush frame; };
layout(std430, binding = BITMASK_TABLE_BINDING_TABLE) writeonly buffer Table { uint table[]; };

void main() {
  uint index = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  uint words = frame.words;
  if (index >= BITMASK_THETA_BINS * BITMASK_R_BINS * words) return;
  uint bin = index / words, word = index % words;
  // The second half of the directions: the complement of the opposite bin's samples (houghOpposite).
  bool opposite = bin / BITMASK_R_BINS >= BITMASK_THETA_BINS / 2u;
  uint from = opposite ? houghOpposite(bin) : bin;
  vec3 line = houghBinLine(from / BITMASK_R_BINS, from % BITMASK_R_BINS);
  uint bits = 0u, valid = 0u;
  for (uint k = 0u; k < 32u; ++k) {
    uint s = word * 32u + k;
    if (s >= frame.samples) break;
    vec2 q = lightSampleOnLight(light, 0u, s, frame.samples);
    if (dot(q, line.xy) > line.z) bits |= 1u << k;
    valid |= 1u << k;
  }
  table[index] = opposite ? ~bits & valid : bits;
}
