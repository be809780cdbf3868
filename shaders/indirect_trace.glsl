// The body of every indirect-ray kernel (indirect_bvh.comp, ...): one invocation per pixel, K
// rays (shared/indirect.h), written to output[pixel] = (rgb one-bounce light, occlusion). The
// includer declares its push constants with an IndirectParams `params`, its structure, and:
//   bool indirectClosest(vec3 origin, vec3 dir, float tMin, float tMax, out float t, out uint triangle)
//   bool indirectOccluded(vec3 origin, vec3 dir, float tMin, float tMax, bool aoRay)  (aoRay: an ao
//     ray; else a shadow ray from a bounce's hit)
//   uint indirectVisits(), uint indirectTests()  (this invocation's traversal counts)
// Not compiled on its own; includers enable GL_KHR_shader_subgroup_basic and _arithmetic, and
// GL_EXT_buffer_reference and _uvec2 (the scene's triangles are read through params.triangles).
#include "shared/frame.h"
#include "shared/indirect.h"

layout(local_size_x = INDIRECT_GROUP_SIZE, local_size_y = INDIRECT_GROUP_SIZE) in;
layout(binding = INDIRECT_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(binding = INDIRECT_BINDING_NORMAL, rgba32f) uniform readonly image2D gNormal;
layout(std430, binding = INDIRECT_BINDING_FRAME) readonly buffer Frame { FrameData frame; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer IndirectTriangleArray { SceneTriangle v[]; };
layout(std430, binding = INDIRECT_BINDING_OUTPUT) writeonly buffer Output { vec4 indirectOut[]; };
layout(std430, binding = INDIRECT_BINDING_COUNTERS) buffer Counters { uint indirectCounters[INDIRECT_COUNTER_WORDS]; };
layout(binding = INDIRECT_BINDING_SHADOW_MAP) uniform sampler2DArray shadowMap;
layout(std430, binding = INDIRECT_BINDING_SHADOW_TEXELS) readonly buffer ShadowTexels { float shadowTexels[]; };
#include "light_texels.glsl"
#include "shadow_map_point.glsl"

void indirectAddCounter(uint word, uint value) {
  if (value == 0u) return;
  uint old = atomicAdd(indirectCounters[word], value);
  if (old > 0xffffffffu - value) atomicAdd(indirectCounters[word + 1u], 1u);
}

void indirectAddCounters(uint rays, uint shadowRays) {
  uint sums[4] = uint[4](subgroupAdd(rays), subgroupAdd(shadowRays), subgroupAdd(indirectVisits()),
                         subgroupAdd(indirectTests()));
  if (subgroupElect()) {
    for (uint i = 0u; i < 4u; ++i) indirectAddCounter(2u * i, sums[i]);
  }
}

void main() {
  ivec2 pix = ivec2(gl_GlobalInvocationID.xy);
  uint rays = 0u, shadowRays = 0u;
  if (pix.x < int(frame.width) && pix.y < int(frame.height)) {
    uint pixel = uint(pix.y) * frame.width + uint(pix.x);
    vec4 position = imageLoad(gPosition, pix);
    vec4 result = vec4(0.0f);
    if (position.w != 0.0f) {
      vec3 n = imageLoad(gNormal, pix).xyz;
      GpuLight light = frame.light;
      vec3 origin = shadowRayOrigin(light, position.xyz, n);
      uint count = params.rays;
      vec3 light3 = vec3(0.0f);
      uint blocked = 0u;
      for (uint k = 0u; k < count; ++k) {
        vec3 dir = indirectDirection(pixel, k, count, params.frame, n);
        ++rays;
        if (params.mode == INDIRECT_AO) {  // uniform over the dispatch
          if (indirectOccluded(origin, dir, 0.0f, params.aoRadius, true)) ++blocked;
          continue;
        }
        float t;
        uint triangle;
        if (!indirectClosest(origin, dir, 0.0f, params.rayMax, t, triangle)) continue;
        IndirectHit hit = indirectHit(IndirectTriangleArray(params.triangles).v[triangle], origin, dir, t, light);
        if (!hit.lit) continue;
        if (params.hitLight == INDIRECT_HIT_SHADOW_MAP) {
          light3 += hit.reflected * shadowMapVisibility(hit.position, hit.face);
          continue;
        }
        ++shadowRays;
        if (!indirectOccluded(hit.shadowOrigin, hit.toLight, 0.0f, hit.shadowEnd, false)) light3 += hit.reflected;
      }
      result = vec4(light3 / float(count), float(blocked) / float(count));
    }
    indirectOut[pixel] = result;
  }
  indirectAddCounters(rays, shadowRays);
}
