#version 450
// The denoiser's spatial filter (hybrid/denoise_pass.h), after the accumulation: each noisy pixel
// (srt's penumbra mask; every covered pixel for frt) becomes a Gaussian-weighted mean of its
// neighbours' accumulated values over a radius that gathers about targetSamples light samples
// (fewer pixels as frames accumulate) but never exceeds the penumbra's width there - from the
// blocker distances the trace found: light size * blocker distance / (receiver-to-light distance -
// blocker distance), in pixels at the receiver's depth - so contacts and hard edges stay sharp.
// Taps are weighted down off the receiver's plane (depth edges) and across creases (normals), so
// shadows do not bleed over silhouettes. Pixels outside the mask are copied: they are exact.
#extension GL_GOOGLE_include_directive : require
#include "shared/denoise.h"
#include "shared/frame.h"
layout(local_size_x = DENOISE_GROUP_SIZE, local_size_y = DENOISE_GROUP_SIZE) in;
layout(binding = DENOISE_SPATIAL_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(binding = DENOISE_SPATIAL_BINDING_NORMAL, rgba32f) uniform readonly image2D gNormal;
layout(std430, binding = DENOISE_SPATIAL_BINDING_FRAME) readonly buffer Frame { FrameData frame; };
layout(std430, binding = DENOISE_SPATIAL_BINDING_ACCUMULATED) readonly buffer Accumulated { vec2 accumulated[]; };  // value, frames
layout(std430, binding = DENOISE_SPATIAL_BINDING_FLAGS) readonly buffer Flags { uint flags[]; };
layout(std430, binding = DENOISE_SPATIAL_BINDING_BLOCKERS) readonly buffer Blockers { float blockers[]; };
layout(std430, binding = DENOISE_SPATIAL_BINDING_VISIBILITY) writeonly buffer Visibility { float visibility[]; };
layout(push_constant) uniform Push { DenoiseSpatialPush push; };
#include "denoise_blockers.glsl"

void main() {
  ivec2 pix = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(frame.width, frame.height);
  if (pix.x >= size.x || pix.y >= size.y) return;
  uint index = uint(pix.y) * frame.width + uint(pix.x);
  vec4 position = imageLoad(gPosition, pix);
  vec2 centre = accumulated[index];
  if (position.w == 0.0 || !noisy(index)) {
    visibility[index] = centre.x;
    return;
  }
  vec3 p = position.xyz;
  vec3 n = imageLoad(gNormal, pix).xyz;
  float pixelWorld = push.pixelScale * distance(p, frame.cameraPosition.xyz);

  // The radius that gathers targetSamples samples, bounded by the penumbra's width where a blocker
  // distance is known nearby.
  float radius = sqrt(push.targetSamples / (3.14159265 * max(centre.y, 1.0) * float(max(frame.spp, 1u))));
  float blocker = nearbyBlockers(pix).x;
  if (blocker > 0.0) {
    float toLight = distance(p, frame.light.position.xyz);
    float width = frame.light.size * blocker / max(toLight - blocker, 1e-3 * toLight);
    radius = min(radius, push.widthFraction * width / pixelWorld);
  }
  radius = clamp(radius, 0.5, push.maxRadius);

  // Surfaces turned away from the light are dark for certain (no ray is traced there): taps on the
  // other side of the terminator from the pixel are not averaged with it.
  bool facing = dot(n, frame.light.position.xyz - p) > 0.0;
  float step = max(radius / float(DENOISE_TAPS), 1.0);
  float sum = centre.x, weights = 1.0;
  for (int j = -DENOISE_TAPS; j <= DENOISE_TAPS; ++j) {
    for (int i = -DENOISE_TAPS; i <= DENOISE_TAPS; ++i) {
      vec2 offset = step * vec2(i, j);
      float d2 = dot(offset, offset);
      if (d2 == 0.0 || d2 > radius * radius * 2.0) continue;
      ivec2 q = pix + ivec2(round(offset));
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
      vec4 qp = imageLoad(gPosition, q);
      if (qp.w == 0.0) continue;
      vec3 qn = imageLoad(gNormal, q).xyz;
      if ((dot(qn, frame.light.position.xyz - qp.xyz) > 0.0) != facing) continue;  // across the terminator
      float offPlane = abs(dot(n, qp.xyz - p)) / (pixelWorld * sqrt(d2));
      float w = exp(-2.0 * d2 / (radius * radius)) * exp(-4.0 * offPlane) * pow(max(dot(n, qn), 0.0), 16.0);
      sum += w * accumulated[uint(q.y) * frame.width + uint(q.x)].x;
      weights += w;
    }
  }
  visibility[index] = sum / weights;
}
