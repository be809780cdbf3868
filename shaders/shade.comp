#version 450
// The one shading pass every method shares: Lambert from the light's centre, scaled by the
// method's visibility and the light's falloff, over a small ambient term. Methods ao and indirect
// add their term: ao scales the ambient term, indirect adds one-bounce light (in the direct light's
// units). With several lights it runs once per light: each adds its direct light to the sum of the
// ones before (the direct buffer, zeroed before the first) over the pixels within the light's range,
// and the last one, over the whole image, writes it. Output is sRGB RGBA8, one uint per pixel.
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
layout(push_constant) uniform Push { ShadePush push; };

const float kAmbient = 0.12;

void main() {
  ivec2 pix = ivec2(push.origin + gl_GlobalInvocationID.xy);
  if (pix.x >= int(frame.width) || pix.y >= int(frame.height)) return;
  uint index = uint(pix.y) * frame.width + uint(pix.x);
  bool last = push.light + 1u == push.lights;
  if (!last && visibility[index] == 0.0) return;  // adds nothing to the sum (shadowed, beyond its range)
  vec4 position = imageLoad(gPosition, pix);
  vec3 rgb;
  if (position.w == 0.0) {
    if (!last) return;
    rgb = mix(vec3(0.60, 0.66, 0.74), vec3(0.33, 0.42, 0.56), float(pix.y) / float(frame.height));
  } else {
    vec3 p = position.xyz;
    vec3 n = imageLoad(gNormal, pix).xyz;
    vec3 l = directionToLight(frame.light, p, frame.light.position.xyz);
    vec3 direct = max(dot(n, l), 0.0) * visibility[index] * lightFalloff(frame.light, p, l) * frame.light.color.rgb;
    if (push.lights > 1u) direct += directSum[index].rgb;
    if (!last) {
      directSum[index] = vec4(direct, 0.0);
      return;
    }
    vec4 extra = push.term != 0u ? indirect[index] : vec4(0.0);
    if (push.term == 2u) direct += extra.rgb;
    rgb = imageLoad(gAlbedo, pix).rgb * (kAmbient * (1.0 - extra.a) + (1.0 - kAmbient) * direct);
  }
  color[index] = packUnorm4x8(vec4(pow(clamp(rgb, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0));
}
