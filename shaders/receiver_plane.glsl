// The receiver's plane as a shadow map sees it (after `frame`, the map as shadow_map_point.glsl
// reads it, and a binding gFaceNormal, the
// G-buffer's face normal, are declared): its NDC depth is affine in texel coordinates under both
// projections, so a plane's depth at any texel follows from its depth and gradient at one point.
// The face normal, not the shading normal, gives the plane: a smoothed mesh's shading normal may
// lean off it. Used by the filters of the lookup (receiver-plane depth comparisons) and by the
// classification (layerOver).
#include "shared/gbuffer.h"
#include "shadow_map_point.glsl"  // faceViewProj


vec3 faceNormalAt(ivec2 pix) { return octahedralDecode(unpackSnorm2x16(imageLoad(gFaceNormal, pix).x)); }

// The NDC depth change per texel step (x, y) of the plane through p (NDC depth z0, at texel
// coordinates e0) with normal n in the map of viewProj: two points on the plane, a texel apart,
// projected. Not finite when the plane is edge-on to the light.
vec2 planeDepthGradient(vec3 p, vec3 n, float texel, mat4 viewProj, vec2 e0, float z0) {
  vec3 t1 = normalize(cross(n, abs(n.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0)));
  vec3 t2 = cross(n, t1);
  float res = float(frame.shadow.resolution);
  vec4 c1 = viewProj * vec4(p + texel * t1, 1.0);
  vec4 c2 = viewProj * vec4(p + texel * t2, 1.0);
  vec2 e1 = (c1.xy / c1.w * 0.5 + 0.5) * res - e0;
  vec2 e2 = (c2.xy / c2.w * 0.5 + 0.5) * res - e0;
  float z1 = c1.z / c1.w - z0;
  float z2 = c2.z / c2.w - z0;
  // g with dot(g, e1) = z1 and dot(g, e2) = z2
  return vec2(z1 * e2.y - z2 * e1.y, e1.x * z2 - e2.x * z1) / (e1.x * e2.y - e1.y * e2.x);
}
