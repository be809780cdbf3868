#version 450
// The denoiser's spatial filter (hybrid/denoise_pass.h), after the accumulation: each noisy pixel
// (srt's penumbra mask; every covered pixel for frt) becomes a Gaussian-weighted mean of its
// neighbours' accumulated values over a radius that gathers about targetSamples light samples
// (fewer pixels as frames accumulate) but never exceeds the penumbra's width there - from the
// blocker distances the trace found: light size * blocker distance / (receiver-to-light distance -
// blocker distance), in pixels at the receiver's depth - so contacts and hard edges stay sharp.
// Taps are weighted down off the receiver's plane (depth edges) and across creases (normals), so
// shadows do not bleed over silhouettes. Pixels outside the mask are copied: they are exact. So
// are those whose taps all lie in tiles whose values span at most DENOISE_UNIFORM (the
// accumulation's ranges): a weighted mean of equal values is that value. Where every pixel is
// noisy (frt, srt tracing all) that is most of a frame: wholly lit or in umbra.
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
layout(std430, binding = DENOISE_SPATIAL_BINDING_RANGES) readonly buffer Ranges { uvec2 ranges[]; };  // float bits: ~lowest, highest
layout(push_constant) uniform Push { DenoiseSpatialPush push; };
#include "denoise_blockers.glsl"

// The radius that gathers targetSamples samples from a pixel whose value averages `frames` frames.
float gatherRadius(float frames) {
  return sqrt(push.targetSamples / (3.14159265 * max(frames, 1.0) * float(max(frame.spp, 1u))));
}

// Whether the values of every tile the pixel's taps may reach - within sqrt(2) radius, rounded,
// of it, the radius at most gatherRadius - span at most DENOISE_UNIFORM. False where that reach
// leaves the tiles around the pixel's own.
bool tilesAgree(ivec2 pix, ivec2 size, float frames) {
  float reach = 1.41421356 * clamp(gatherRadius(frames), 0.5, push.maxRadius) + 0.5;
  if (reach > float(DENOISE_GROUP_SIZE)) return false;
  ivec2 lo = max(pix - ivec2(reach), ivec2(0)) / DENOISE_GROUP_SIZE;
  ivec2 hi = min(pix + ivec2(reach), size - 1) / DENOISE_GROUP_SIZE;
  uint tilesX = (frame.width + DENOISE_GROUP_SIZE - 1u) / DENOISE_GROUP_SIZE;
  uint lowest = 0xffffffffu, highest = 0u;
  for (int y = lo.y; y <= hi.y; ++y) {
    for (int x = lo.x; x <= hi.x; ++x) {
      uvec2 range = ranges[uint(y) * tilesX + uint(x)];
      lowest = min(lowest, ~range.x);
      highest = max(highest, range.y);
    }
  }
  return uintBitsToFloat(highest) - uintBitsToFloat(lowest) <= DENOISE_UNIFORM;
}

void main() {
  ivec2 pix = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(frame.width, frame.height);
  if (pix.x >= size.x || pix.y >= size.y) return;
  uint index = uint(pix.y) * frame.width + uint(pix.x);
  vec2 centre = accumulated[index];  // frames 0: not covered
  if (centre.y == 0.0 || !noisy(index) || (push.skipAgreeing != 0u && tilesAgree(pix, size, centre.y))) {
    visibility[index] = centre.x;
    return;
  }
  vec3 p = imageLoad(gPosition, pix).xyz;
  vec3 n = imageLoad(gNormal, pix).xyz;
  float pixelWorld = push.pixelScale * distance(p, frame.cameraPosition.xyz);

  // The radius that gathers targetSamples samples, bounded by the penumbra's width where a blocker
  // distance is known nearby.
  float radius = gatherRadius(centre.y);
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
      float c = max(dot(n, qn), 0.0);  // the normals' weight: c^16, squared four times (no pow)
      c *= c;
      c *= c;
      c *= c;
      float w = exp(-2.0 * d2 / (radius * radius) - 4.0 * offPlane) * (c * c);
      sum += w * accumulated[uint(q.y) * frame.width + uint(q.x)].x;
      weights += w;
    }
  }
  visibility[index] = sum / weights;
}
