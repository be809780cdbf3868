#version 450
// The denoiser's temporal accumulation (hybrid/denoise_pass.h), before its spatial filter: each
// noisy pixel's visibility (its light samples of this frame) is averaged with its history - the
// running mean where the same surface point was in the previous frame, found by reprojecting the
// point with the previous camera (bilinear over the 4 pixels around it), or, after the light moved,
// the point where the shadow now on it fell (shadowBefore) - over at most maxHistory frames. A
// pixel's history is dropped where it saw another surface (disocclusion: off the receiver's plane
// or away from the point by more than a few pixels). Where the image may have changed since (clipSigmas > 0: the
// light, the geometry or the camera moved), it is also clipped to the current 5x5 neighbourhood's mean +- clipSigmas
// deviations, so that they leave no trail: where the neighbourhood agrees (outside penumbrae) the
// history must agree too, up to what so few samples can tell. A still scene is not clipped: any clip
// of few-sample neighbourhoods biases penumbrae (foliage at 32 frames: rmse 0.026 clipped, 0.012 not).
// Pixels outside the mask are exact: their value, with a full count, is their history. Each
// workgroup also writes the range of its covered pixels' results (the spatial filter's tiles).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#include "shared/denoise.h"
#include "shared/frame.h"
layout(local_size_x = DENOISE_GROUP_SIZE, local_size_y = DENOISE_GROUP_SIZE) in;
layout(binding = DENOISE_ACCUMULATE_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(binding = DENOISE_ACCUMULATE_BINDING_NORMAL, rgba32f) uniform readonly image2D gNormal;
layout(std430, binding = DENOISE_ACCUMULATE_BINDING_FRAME) readonly buffer Frame { FrameData frame; };
layout(std430, binding = DENOISE_ACCUMULATE_BINDING_VISIBILITY) readonly buffer Visibility { float visibility[]; };
layout(std430, binding = DENOISE_ACCUMULATE_BINDING_FLAGS) readonly buffer Flags { uint flags[]; };
layout(std430, binding = DENOISE_ACCUMULATE_BINDING_HISTORY_IN) readonly buffer HistoryIn { DenoiseHistory historyIn[]; };
layout(std430, binding = DENOISE_ACCUMULATE_BINDING_HISTORY_OUT) writeonly buffer HistoryOut { DenoiseHistory historyOut[]; };
layout(std430, binding = DENOISE_ACCUMULATE_BINDING_ACCUMULATED) writeonly buffer Accumulated { vec2 accumulated[]; };  // value, frames
layout(std430, binding = DENOISE_ACCUMULATE_BINDING_BLOCKERS) readonly buffer Blockers { float blockers[]; };
layout(std430, binding = DENOISE_ACCUMULATE_BINDING_RANGES) buffer Ranges { uvec2 ranges[]; };  // float bits: ~lowest, highest
layout(push_constant) uniform Push { DenoiseAccumulatePush push; };
#include "denoise_blockers.glsl"

// The history's value in 16-bit fixed point (rounded to nearest: a float16's rounding, truncating
// on some drivers, dragged a running mean down by half a unit a frame) and its frame count.
uint packHistory(float value, float frames) {
  return uint(round(clamp(value, 0.0, 1.0) * 65535.0)) | (uint(frames) << 16u);
}
vec2 unpackHistory(uint packed) {
  return vec2(float(packed & 0xffffu) / 65535.0, float(packed >> 16u));
}

// Where on p's surface the shadow that now falls on p fell in the history's frame: a light that
// moved by lightShift moves the shadow of a blocker b from p (of D from p to the light) by
// -lightShift * b / (D - b), projected onto p's plane along the light's direction. p itself where
// the nearby blockers do not agree on one distance (fewer than DENOISE_FOLLOW_BLOCKERS known, or
// spread over more than followSpread of their mean: foliage, where one shift moves the history
// wrongly) or none is near (lit).
vec3 shadowBefore(vec3 p, vec3 n, ivec2 pix) {
  if (push.lightShift.xyz == vec3(0.0)) return p;
  vec4 b4 = nearbyBlockers(pix);
  float b = b4.x;
  vec3 toLight = frame.light.position.xyz - p;
  float d = length(toLight);
  vec3 l = toLight / d;
  float nl = dot(n, l);
  if (b4.w < float(DENOISE_FOLLOW_BLOCKERS) || nl < 0.05 || b4.z - b4.y > push.followSpread * b) return p;
  vec3 shift = push.lightShift.xyz * (b / max(d - b, 1e-3 * d));
  return p + shift - l * (dot(n, shift) / nl);
}

// Accumulates pixel pix (in the image); returns its result, or -1 where it is not covered.
float accumulate(ivec2 pix, ivec2 size) {
  uint index = uint(pix.y) * frame.width + uint(pix.x);
  vec4 position = imageLoad(gPosition, pix);
  float current = visibility[index];
  if (position.w == 0.0) {
    historyOut[index] = DenoiseHistory(vec3(0.0), 0u);
    accumulated[index] = vec2(current, 0.0);
    return -1.0;
  }
  vec3 p = position.xyz;
  float result = current, frames = 1.0;
  if (!noisy(index)) {
    frames = push.maxHistory;  // exact
  } else if (push.useHistory != 0u) {
    vec3 n = imageLoad(gNormal, pix).xyz;
    vec3 hp = shadowBefore(p, n, pix);
    vec4 clip = push.previousViewProj * vec4(hp, 1.0);
    // The history where hp was, bilinear over the 4 pixels around it that saw the same surface
    // (a shadow or a camera moving by less than a pixel a frame still moves the history).
    vec2 at = (clip.xy / max(clip.w, 1e-30) * 0.5 + 0.5) * vec2(size) - 0.5;
    ivec2 q0 = ivec2(floor(at));
    vec2 f = at - vec2(q0);
    int taps = 4;
    if (push.stillCamera != 0u && hp == p) {  // its own pixel's (rounding would spread it over 4)
      q0 = pix;
      f = vec2(0.0);
      taps = 1;
    }
    float pixelWorld = push.pixelScale * distance(p, frame.cameraPosition.xyz);
    float weight = 0.0, value = 0.0, count = 1e9;
    for (int k = 0; k < taps && clip.w > 0.0; ++k) {
      ivec2 q = q0 + ivec2(k & 1, k >> 1);
      float w = ((k & 1) != 0 ? f.x : 1.0 - f.x) * ((k >> 1) != 0 ? f.y : 1.0 - f.y);
      if (w <= 0.0 || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
      DenoiseHistory h = historyIn[uint(q.y) * frame.width + uint(q.x)];
      vec2 vc = unpackHistory(h.valueCount);
      if (vc.y > 0.0 && abs(dot(n, h.position - hp)) < 2.0 * pixelWorld && distance(h.position, hp) < 4.0 * pixelWorld) {
        weight += w;
        value += w * vc.x;
        count = min(count, vc.y);
      }
    }
    if (weight > 0.0) {
      float history = value / weight;
      float sum = 0.0, squares = 0.0, neighbours = 0.0;
      for (int dy = -2; dy <= 2 && push.clipSigmas > 0.0; ++dy) {
        for (int dx = -2; dx <= 2; ++dx) {
          ivec2 r = clamp(pix + ivec2(dx, dy), ivec2(0), size - 1);
          if (imageLoad(gPosition, r).w == 0.0) continue;
          float v = visibility[uint(r.y) * frame.width + uint(r.x)];
          sum += v;
          squares += v * v;
          neighbours += 1.0;
        }
      }
      if (neighbours > 0.0) {
        float mean = sum / neighbours;
        float deviation = sqrt(max(squares / neighbours - mean * mean, 0.0));
        // N neighbours whose N * spp samples all agree bound the value only to within 3 / (N * spp)
        // (the rule of three): clipping to their value exactly would drag penumbra tails to 0 or 1.
        float spread = push.clipSigmas * deviation + 3.0 / (neighbours * float(max(frame.spp, 1u)));
        history = clamp(history, mean - spread, mean + spread);
      }
      frames = min(count + 1.0, push.maxHistory);
      result = mix(history, current, 1.0 / frames);
    }
  }
  historyOut[index] = DenoiseHistory(p, packHistory(result, frames));
  accumulated[index] = vec2(result, frames);
  return result;
}

void main() {
  ivec2 pix = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(frame.width, frame.height);
  float result = all(lessThan(pix, size)) ? accumulate(pix, size) : -1.0;
  // The tile's range: its subgroups' reduced, then one atomic each into the range (cleared to 0).
  // Non-negative floats order as their bits do.
  uint bits = floatBitsToUint(result) & 0x7fffffffu;  // -0 as 0
  uint highest = subgroupMax(result >= 0.0 ? bits : 0u);
  uint lowestInverted = subgroupMax(result >= 0.0 ? ~bits : 0u);
  if (subgroupElect()) {
    uint tile = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    atomicMax(ranges[tile].x, lowestInverted);
    atomicMax(ranges[tile].y, highest);
  }
}
