#version 450
// Light fit: the bounds, in the whole-scene map's NDC, of the covered pixels' points that lie in
// front of the light's map (receivers the map is looked up for). Each invocation reduces a block of
// pixels in a loop, subgroups reduce in registers, their leaders in shared memory, and the
// workgroup adds its bounds to the global ones with one atomic each (one shared atomic per pixel
// cost 20 ms at 1024^2 on lavapipe, four times the whole pass now).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "shared/light_fit.h"
layout(local_size_x = LIGHT_FIT_GROUP_SIZE, local_size_y = LIGHT_FIT_GROUP_SIZE) in;
layout(binding = LIGHT_FIT_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(std430, binding = LIGHT_FIT_BINDING_BOUNDS) buffer Bounds { LightFitBounds bounds; };
layout(push_constant) uniform PushBlock { LightFitPush push; };

shared uint sMinX, sMinY, sMaxX, sMaxY, sCount;

void main() {
  if (gl_LocalInvocationIndex == 0u) {
    sMinX = sMinY = 0xffffffffu;
    sMaxX = sMaxY = 0u;
    sCount = 0u;
  }
  barrier();
  vec2 blockLo = vec2(2.0), blockHi = vec2(-2.0);
  uint blockCount = 0u;
  ivec2 first = ivec2(gl_GlobalInvocationID.xy) * LIGHT_FIT_BLOCK;
  for (int y = 0; y < LIGHT_FIT_BLOCK; ++y) {
    for (int x = 0; x < LIGHT_FIT_BLOCK; ++x) {
      ivec2 pix = first + ivec2(x, y);
      if (pix.x >= int(push.width) || pix.y >= int(push.height)) continue;
      vec4 position = imageLoad(gPosition, pix);
      vec4 clip = push.viewProj * vec4(position.xyz, 1.0);
      if (position.w == 0.0 || clip.w <= 0.0) continue;
      vec2 ndc = clamp(clip.xy / clip.w, vec2(-1.0), vec2(1.0));  // beyond the scene's map nothing is looked up
      blockLo = min(blockLo, ndc);
      blockHi = max(blockHi, ndc);
      ++blockCount;
    }
  }
  vec2 lo = subgroupMin(blockLo);
  vec2 hi = subgroupMax(blockHi);
  uint count = subgroupAdd(blockCount);
  if (subgroupElect() && count > 0u) {
    atomicMin(sMinX, lightFitOrdered(lo.x));
    atomicMin(sMinY, lightFitOrdered(lo.y));
    atomicMax(sMaxX, lightFitOrdered(hi.x));
    atomicMax(sMaxY, lightFitOrdered(hi.y));
    atomicAdd(sCount, count);
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u && sCount > 0u) {
    atomicMin(bounds.minX, sMinX);
    atomicMin(bounds.minY, sMinY);
    atomicMax(bounds.maxX, sMaxX);
    atomicMax(bounds.maxY, sMaxY);
    atomicAdd(bounds.receivers, sCount);
  }
}
