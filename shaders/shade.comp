#version 450
// The one shading pass every method shares: Lambert from the light's centre, scaled by the
// method's visibility and the light's falloff, over a small ambient term. Methods ao and indirect
// add their term: ao scales the ambient term, indirect adds one-bounce light (in the direct light's
// units). A frame of several lights shades them in batches (ShadeLight): a pixel sums the lights its
// tile lists whose range rectangle holds it; a batch before the frame's last writes its sum to the
// direct buffer, which the next adds. Output is sRGB RGBA8, one uint per pixel.
#extension GL_GOOGLE_include_directive : require
#include "shared/frame.h"
#include "shared/raster.h"
layout(local_size_x = LOOKUP_GROUP_SIZE, local_size_y = LOOKUP_GROUP_SIZE) in;
layout(binding = SHADE_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(binding = SHADE_BINDING_NORMAL, rgba32f) uniform readonly image2D gNormal;
layout(binding = SHADE_BINDING_ALBEDO, rgba8) uniform readonly image2D gAlbedo;
layout(std430, binding = SHADE_BINDING_FRAME) readonly buffer Frame { FrameData frame; };
layout(std430, binding = SHADE_BINDING_VISIBILITY) readonly buffer Visibility { float visibility[]; };
layout(std430, binding = SHADE_BINDING_COLOR) writeonly buffer Color { uint color[]; };
layout(std430, binding = SHADE_BINDING_INDIRECT) readonly buffer Indirect { vec4 indirect[]; };  // rgb one-bounce light, a occlusion
layout(std430, binding = SHADE_BINDING_DIRECT) buffer Direct { vec4 directSum[]; };
layout(std430, binding = SHADE_BINDING_LIGHTS) readonly buffer Lights { ShadeLight lights[]; };
layout(std430, binding = SHADE_BINDING_TILES) readonly buffer Tiles { uint tiles[]; };
layout(push_constant) uniform Push { ShadePush push; };

// The direct light of `light` at p, seen `visible` of it.
vec3 directLight(GpuLight light, vec3 p, vec3 n, float visible) {
  vec3 l = directionToLight(light, p, light.position.xyz);
  return max(dot(n, l), 0.0) * visible * lightFalloff(light, p, l) * light.color.rgb;
}

void main() {
  ivec2 pix = ivec2(push.origin + gl_GlobalInvocationID.xy);
  if (pix.x >= int(frame.width) || pix.y >= int(frame.height)) return;
  uint index = uint(pix.y) * frame.width + uint(pix.x);
  bool last = push.last != 0u;
  vec4 position = imageLoad(gPosition, pix);
  vec3 rgb;
  if (position.w == 0.0) {
    if (!last) return;
    rgb = mix(vec3(0.60, 0.66, 0.74), vec3(0.33, 0.42, 0.56), float(pix.y) / float(frame.height));
  } else {
    vec3 p = position.xyz;
    vec3 n = imageLoad(gNormal, pix).xyz;
    vec3 direct = vec3(0.0);
    if (push.batched == 0u) {
      direct = directLight(frame.light, p, n, visibility[index]);
    } else {
      uint tile = uint(pix.y / SHADE_TILE) * push.tilesX + uint(pix.x / SHADE_TILE);
      for (uint i = tiles[tile]; i < tiles[tile + 1u]; ++i) {
        uint k = tiles[i];
        uvec4 rect = lights[k].rect;
        if (uint(pix.x) < rect.x || uint(pix.y) < rect.y || uint(pix.x) >= rect.z || uint(pix.y) >= rect.w) continue;
        float visible = visibility[lights[k].offset + (uint(pix.y) - rect.y) * (rect.z - rect.x) + uint(pix.x) - rect.x];
        if (visible != 0.0) direct += directLight(lights[k].light, p, n, visible);  // else it adds nothing
      }
    }
    if (push.sum != 0u) direct += directSum[index].rgb;
    if (!last) {
      directSum[index] = vec4(direct, 0.0);
      return;
    }
    vec4 extra = push.term != 0u ? indirect[index] : vec4(0.0);
    if (push.term == 2u) direct += extra.rgb;
    rgb = imageLoad(gAlbedo, pix).rgb * (SHADE_AMBIENT * (1.0 - extra.a) + (1.0 - SHADE_AMBIENT) * direct);
  }
  color[index] = packUnorm4x8(vec4(pow(clamp(rgb, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0));
}
